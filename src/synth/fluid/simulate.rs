//! A fluid layout simulated through the release's timeline with `physics::fluid` (position-based
//! fluids as Obi configured them): the tank, sticks, containers and emitters become capsule
//! colliders and edge emitters; every emitter is its own fluid key (`Later Emitted Blue Fluid`
//! apart from `Blue Fluid`) with its fluid's material.
//!
//! Timeline (`FORMAT.md` §3.1): emitters open at update 2, later emitters at update 460; frames
//! are captured after every second update up to update 500 (250 frames); the factual run goes on
//! to update 700, a counterfactual run stops at 500, without its removed stick and without the
//! later emitters. Each update records which colliders each particle touches (the release's
//! Obi collision events), for the tracking statistics.

use super::layout::{
    EMITTER_CAPACITY, EMITTER_WIDTH, Layout, ORIGIN, ROOM_BELOW, SIDE_CLEARANCE, STICK_SCALE, TANK,
    WALL_THICKNESS, to_world,
};
use crate::physics::fluid::{
    Collider, Emitter, FluidError, FluidMaterial, FluidParameters, FluidWorld,
};

/// The release's timeline of a fluid trial, in updates (`FluidSlidesConfig`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Timeline {
    /// Updates of the factual run (700).
    pub factual_updates: usize,
    /// Updates captured (500; frames after every second one), also the length of a
    /// counterfactual run.
    pub capture_updates: usize,
    /// The update the emitters open at (2).
    pub emitters_open: usize,
    /// The update the later (predictive) emitters open at (460).
    pub later_emitters_open: usize,
    /// Particles each emitter releases (1,500).
    pub capacity: usize,
}

impl Timeline {
    /// The release's.
    pub const RELEASE: Timeline = Timeline {
        factual_updates: 700,
        capture_updates: 500,
        emitters_open: 2,
        later_emitters_open: 460,
        capacity: EMITTER_CAPACITY,
    };

    /// Frames captured.
    pub fn frames(&self) -> usize {
        self.capture_updates / 2
    }
}

/// Emitter speed and largest random velocity, units/s.
const EMITTER_SPEED: f64 = 0.7;
const EMITTER_RANDOM_VELOCITY: f64 = 0.4;
/// How far past touching a particle still counts as in contact, in spacings: the density
/// constraint holds resting particles about half a spacing off a surface, with some jitter.
const CONTACT_MARGIN_SPACINGS: f64 = 0.3;
/// Half the thickness of a cup's walls and of an emitter's side walls, units.
const THIN_HALF_THICKNESS: f64 = 0.025;
/// Height of an emitter's box, units (its scale 0.25 turned upright).
const EMITTER_HEIGHT: f64 = 0.25;

/// A collider with the scene object name it stands for.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedCollider {
    /// Scene object name (`Red Stick`, `Blue Container Bottom Floor`, `Floor`).
    pub name: String,
    /// Its geometry and material.
    pub collider: Collider,
}

/// One emitter of the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneEmitter {
    /// Fluid key (`Blue Fluid`, `Later Emitted Blue Fluid`), also its object name.
    pub name: String,
    /// Index of the layout's fluid it emits.
    pub fluid: usize,
    /// Centre of its edge, world units.
    pub centre: [f64; 2],
    /// Whether it is a later (predictive) emitter.
    pub later: bool,
}

/// The simulated objects of a layout.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidScene {
    /// Every collider (at most 64, so a particle's contacts fit a bit mask).
    pub colliders: Vec<NamedCollider>,
    /// Emitters: the fluids' own, then the later ones.
    pub emitters: Vec<SceneEmitter>,
}

fn collider(start: [f64; 2], end: [f64; 2], half_thickness: f64) -> Collider {
    Collider {
        start,
        end,
        half_thickness,
        friction: 0.3,
        stickiness: 0.03,
    }
}

impl FluidScene {
    /// The colliders and emitters of `layout`.
    pub fn new(layout: &Layout) -> FluidScene {
        let mut colliders = Vec::new();
        let mut add = |name: String, start, end, half| {
            colliders.push(NamedCollider {
                name,
                collider: collider(start, end, half),
            });
        };
        // Tank walls: their inner faces at x = ±(W/2 + 0.2) and the floor's top 1.5 units
        // below the containers' band (the release's `pos_*_vert*`, `pos_y_hori1`).
        let half_wall = WALL_THICKNESS / 2.0;
        let inner_x = TANK[0] / 2.0 + SIDE_CLEARANCE;
        let floor_top = ORIGIN[1] - RECEPTOR_BAND - ROOM_BELOW;
        let top = ORIGIN[1] + TANK[1] + 1.6 + WALL_THICKNESS;
        for (name, x) in [("Left Vertical Wall", -1.0), ("Right Vertical Wall", 1.0)] {
            let centre_x = x * (inner_x + half_wall);
            add(
                name.to_string(),
                [centre_x, floor_top - WALL_THICKNESS],
                [centre_x, top],
                half_wall,
            );
        }
        add(
            "Floor".to_string(),
            [-inner_x - WALL_THICKNESS, floor_top - half_wall],
            [inner_x + WALL_THICKNESS, floor_top - half_wall],
            half_wall,
        );
        for stick in &layout.sticks {
            let (start, end) = stick.world();
            add(stick.name.clone(), start, end, STICK_SCALE[0] / 2.0);
        }
        for container in &layout.containers {
            for funnel in [&container.left, &container.right] {
                let (start, end) = funnel.world();
                add(funnel.name.clone(), start, end, STICK_SCALE[0] / 2.0);
            }
            let centre = to_world(container.position);
            let [width, height] = container.scale;
            let (left, right) = (centre[0] - width / 2.0, centre[0] + width / 2.0);
            let (bottom, rim) = (centre[1] - height / 2.0, centre[1] + height / 2.0);
            let inset = THIN_HALF_THICKNESS;
            add(
                format!("{} Bottom Floor", container.name),
                [left, bottom + inset],
                [right, bottom + inset],
                inset,
            );
            for (side, x) in [("Left", left + inset), ("Right", right - inset)] {
                add(
                    format!("{} {side} Vertical Wall", container.name),
                    [x, bottom],
                    [x, rim],
                    inset,
                );
            }
        }
        let mut emitters = Vec::new();
        for (index, fluid) in layout.fluids.iter().enumerate() {
            emitters.push(SceneEmitter {
                name: fluid.name.clone(),
                fluid: index,
                centre: to_world(fluid.emitter),
                later: false,
            });
        }
        for (index, fluid) in layout.fluids.iter().enumerate() {
            if let Some(position) = fluid.later_emitter {
                emitters.push(SceneEmitter {
                    name: fluid.later_name(),
                    fluid: index,
                    centre: to_world(position),
                    later: true,
                });
            }
        }
        // Each emitter box has two side walls (`<emitter> Emitter Left Wall`, ...).
        for emitter in &emitters {
            let [x, y] = emitter.centre;
            let half = EMITTER_WIDTH / 2.0 + THIN_HALF_THICKNESS;
            for (side, sign) in [("Left", -1.0), ("Right", 1.0)] {
                add(
                    format!("{} Emitter {side} Wall", emitter.name),
                    [x + sign * half, y - EMITTER_HEIGHT / 2.0],
                    [x + sign * half, y + EMITTER_HEIGHT / 2.0],
                    THIN_HALF_THICKNESS,
                );
            }
        }
        FluidScene {
            colliders,
            emitters,
        }
    }
}

/// Height of the containers' band (cups and funnels) under the sticks' band, units: the
/// release's `receptor_h_relative · H`.
const RECEPTOR_BAND: f64 = 0.5 * TANK[1];

/// What a run changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunKind<'a> {
    /// The factual run: every emitter, all its updates, frames captured.
    Factual,
    /// A counterfactual run without the named stick: the fluids' own emitters, the captured
    /// updates only.
    Without(&'a str),
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidRun {
    /// Particle positions after every second captured update (factual runs only),
    /// world units; particles are only ever appended, so frame `k` holds the first
    /// `frames[k].len()` particles.
    pub frames: Vec<Vec<[f64; 2]>>,
    /// Emitter (index into [`FluidScene::emitters`]) of each particle.
    pub emitter_of: Vec<usize>,
    /// Per particle, a bit per collider (index into [`FluidScene::colliders`]) it touched.
    pub touched: Vec<u64>,
    /// Positions after the last update, world units.
    pub final_positions: Vec<[f64; 2]>,
    /// Updates simulated.
    pub updates: usize,
}

/// Runs `scene` with the fluids of `layout` as `kind` says, through `timeline`; `seed` drives the emitters' random
/// velocities (the same for every run of a video, so a counterfactual run differs from the
/// factual one only by what it changes).
///
/// # Errors
/// The solver's: a particle that is not finite.
pub fn run(
    layout: &Layout,
    scene: &FluidScene,
    kind: RunKind<'_>,
    timeline: &Timeline,
    seed: u64,
) -> Result<FluidRun, FluidError> {
    let parameters = FluidParameters::default();
    let materials: Vec<FluidMaterial> = scene
        .emitters
        .iter()
        .map(|emitter| {
            let fluid = &layout.fluids[emitter.fluid];
            FluidMaterial {
                rest_density: fluid.density,
                viscosity: fluid.viscosity(),
                surface_tension: fluid.surface_tension,
            }
        })
        .collect();
    let removed = match kind {
        RunKind::Factual => None,
        RunKind::Without(name) => Some(name),
    };
    // Removed colliders stay in the list as far-away points, so collider indices (and the
    // contact bits) mean the same in every run.
    let colliders: Vec<Collider> = scene
        .colliders
        .iter()
        .map(|named| {
            if Some(named.name.as_str()) == removed {
                collider([1e6, 1e6], [1e6, 1e6], 0.0)
            } else {
                named.collider
            }
        })
        .collect();
    let emitters: Vec<Emitter> = scene
        .emitters
        .iter()
        .enumerate()
        .filter(|(_, emitter)| kind == RunKind::Factual || !emitter.later)
        .map(|(index, emitter)| Emitter {
            fluid: index,
            centre: [emitter.centre[0], emitter.centre[1] - EMITTER_HEIGHT / 2.0],
            direction: [0.0, -1.0],
            width: EMITTER_WIDTH,
            speed: EMITTER_SPEED,
            random_velocity: EMITTER_RANDOM_VELOCITY,
            capacity: timeline.capacity,
            opens_at: if emitter.later {
                timeline.later_emitters_open
            } else {
                timeline.emitters_open
            },
        })
        .collect();
    let spacing = parameters.spacing;
    let mut world = FluidWorld::new(parameters, materials, colliders.clone(), emitters, seed)?;
    let updates = match kind {
        RunKind::Factual => timeline.factual_updates,
        RunKind::Without(_) => timeline.capture_updates,
    };
    let reach = spacing * (0.5 + CONTACT_MARGIN_SPACINGS);
    let mut touched: Vec<u64> = Vec::new();
    let mut frames = Vec::new();
    for update in 1..=updates {
        world.step()?;
        touched.resize(world.positions().len(), 0);
        for (bits, &position) in touched.iter_mut().zip(world.positions()) {
            for (index, collider) in colliders.iter().enumerate() {
                if collider.near(position, reach) && collider.surface_gap(position).0 < reach {
                    *bits |= 1 << index;
                }
            }
        }
        if kind == RunKind::Factual && update % 2 == 0 && update <= timeline.capture_updates {
            frames.push(world.positions().to_vec());
        }
    }
    Ok(FluidRun {
        frames,
        emitter_of: world.fluid_of().to_vec(),
        touched,
        final_positions: world.positions().to_vec(),
        updates,
    })
}
