//! Cloth runs by simulation (`--dynamics simulate`): one half of the table as the video shows it
//! at the start (its pillars and plates where they stand, the cloth where it spawns), the cloth
//! given the properties read from the video (`infer`) and dragged by the handle as far as the
//! video shows, run through the release's timeline on the XPBD solver (`physics::xpbd`) at an
//! inference setting ([`ClothModel`]), and read as the release reads its runs: which boxes
//! collide, which touch at the end, each box's end pose.
//!
//! Units are the scene's: lengths in units (metres), time in seconds, one update 1/60 s, `y`
//! up, the table's top at `y = 0`, masses in kg.
//!
//! What the video cannot show is assumed, each a stated choice:
//!
//! * **Masses.** The release draws each box's mass from a pool set by its half's cloth friction
//!   (low: plates 2 kg, pillars 6.5 kg; high: plates 4 kg, pillars 12 kg; and in both an
//!   effectively immovable 99999 kg for about one pillar in four and two plates in five). A box
//!   standing still before the cloth reaches it shows none of this, but the cloth's path does:
//!   the cloth cannot go through the place a box stands, so a box whose place it never goes
//!   through (`infer::goes_through`) was not moved by it, and gets its pool's immovable mass;
//!   every other box was moved and gets its pool's movable mass, or, where the friction is not
//!   told, the mean of the two pools' ([`assumed_mass`]). On the 100 videos of seed 2026
//!   (in-sample) the cloth never went through the places of 273 boxes: every one of the 183
//!   immovable ones, 78 light ones it did not move, 12 light ones that fell some other way; it
//!   went through the places of 299 light ones, 275 of which fell. Read from pixels, with no
//!   3-D path of the cloth, a box is undisturbed when its own masks show it standing still
//!   where it started (`motion`).
//! * **The cloth's mass** is the generator's areal mass (0.1 kg/m²), which the release does not
//!   record.
//! * **The handle** drags at the release's 3 units/s along +z for the distance the gripped row
//!   travels in the video, holds still, and lets go at update 190.
//!
//! Input: a [`SeenHalf`] and a [`ClothModel`]. Output: a [`HalfRun`].

use std::collections::BTreeSet;

use crate::dataset::cloth::names::Shape;
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{BoxRecord, Friction, VALUES};
use crate::physics::vector3::{self as v3, Quaternion, Vector};
use crate::physics::xpbd::{
    BoxBody, Sheet, SheetProperties, SheetSpec, World, XpbdError, XpbdSettings,
};
// The release's timeline and the generator's cloth: facts of the scene, not of the model.
use crate::synth::cloth::layout::{CLOTH_RESOLUTION, mass_pools};
use crate::synth::cloth::simulate::{
    CLOTH_AREAL_MASS, END_UPDATE, FRICTION_SCALE, OBJECT_FRICTION, PULL_SPEED, RADIUS_PER_SPACING,
    RELEASE_UPDATE, SPAWN_UPDATE,
};

/// How close two boxes' surfaces must come to touch, units: Unity's default contact offset
/// (0.01), within which the release's physics reports a contact. A geometric reading, since the
/// solver's contacts flicker for resting boxes (`World::box_pairs_within`): over the last 40
/// updates of the 20 halves of `bench physics --scenario cloth`, 11 of the 22 pairs in contact
/// at the fine reference (50 substeps) and 5 of 23 at the default came and went.
pub const TOUCH_TOLERANCE: f64 = 0.01;

/// Why a half could not be simulated.
#[derive(Debug, thiserror::Error)]
pub enum SimulationError {
    /// The seen cloth is no cloth to spawn.
    #[error("the cloth seen at the spawn {0}")]
    Cloth(String),
    /// The solver refused a box or a setting, or stopped being finite.
    #[error(transparent)]
    Solver(#[from] XpbdError),
}

/// The inference setting: the cloth's grid and the solver's steps. The default, a 16 × 16 grid
/// (over the video's cloth, its particles twice the video's) at 20 substeps of 1 iteration, is
/// the point of `bench physics --scenario cloth` with the smallest decided-label errors, over
/// 40 halves, at no more than a tenth of its reference's run time (`docs/data/cloth.md`, *Error
/// against run time*). Why not the video's 31 × 31: at the few substeps a tenth of the run time
/// allows, its long chain of particles from the handle does not converge (the cloth swings down
/// ahead of the fine reference's and meets the boxes differently); half the particles converge
/// at a few substeps, and many substeps of one iteration each beat fewer of more.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClothModel {
    /// Particles along a side of the simulated cloth (the video's cloth has 31).
    pub resolution: usize,
    /// Solver substeps per update.
    pub substeps: usize,
    /// Constraint iterations per substep.
    pub iterations: usize,
    /// The solver's friction per unit of the release's coefficient (the truth solver's
    /// calibration, [`FRICTION_SCALE`]).
    pub friction_scale: f64,
    /// A cloth particle's radius per grid spacing (the generator's [`RADIUS_PER_SPACING`]): the
    /// cloth's thickness is twice the radius, so a coarser grid at the same ratio simulates a
    /// thicker cloth, which holds boxes it lies between further apart.
    pub radius_per_spacing: f64,
}

/// The default inference setting, a constant so that `bench physics` takes its default point from
/// it rather than a copy.
pub const INFERENCE_MODEL: ClothModel = ClothModel {
    resolution: 16,
    substeps: 20,
    iterations: 1,
    friction_scale: FRICTION_SCALE,
    radius_per_spacing: RADIUS_PER_SPACING,
};

impl Default for ClothModel {
    fn default() -> Self {
        INFERENCE_MODEL
    }
}

/// A pillar or plate as the video shows it before anything moves.
#[derive(Debug, Clone, PartialEq)]
pub struct SeenBox {
    /// Its name (`Green Plate`).
    pub name: String,
    /// Pillar or plate.
    pub shape: Shape,
    /// Full extents along its local axes, units.
    pub size: Vector,
    /// Its centre, units.
    pub position: Vector,
    /// Its orientation.
    pub orientation: Quaternion,
    /// Its mass where it is known (a benchmark case built from the generator's records), kg;
    /// `None` takes [`assumed_mass`].
    pub mass: Option<f64>,
    /// Whether the video shows the cloth never going through the place it stands
    /// (`infer::goes_through`): nothing moved it.
    pub undisturbed: bool,
}

impl SeenBox {
    /// The box of `record` where it starts, of `mass` where it is known.
    pub fn from_record(record: &BoxRecord, mass: Option<f64>) -> SeenBox {
        SeenBox {
            name: record.name.clone(),
            shape: record.shape,
            size: record.scale,
            position: record.start_position,
            orientation: unity_rotation(record.start_rotation),
            mass,
            undisturbed: false,
        }
    }
}

/// The cloth of a half as the video shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct SeenCloth {
    /// Its particles at the spawn (a flat square grid), units.
    pub spawn: Vec<Vector>,
    /// Stretch compliance, m/N (0.011 or 0).
    pub stretch_compliance: f64,
    /// Max bending, units (0.013 or 0.035).
    pub max_bending: f64,
    /// Its friction class, if the video tells it.
    pub friction: Option<Friction>,
    /// How far the handle drags it, units.
    pub pull_distance: f64,
}

/// A half of the table as the video shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct SeenHalf {
    /// Its pillars and plates.
    pub boxes: Vec<SeenBox>,
    /// Its cloth.
    pub cloth: SeenCloth,
}

/// What a simulated half did.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfRun {
    /// Each box's end pose, in the order of [`SeenHalf::boxes`].
    pub end_poses: Vec<Pose>,
    /// Each box's centre and orientation at the end.
    pub end_states: Vec<(Vector, Quaternion)>,
    /// The pairs of boxes (indices, smaller first) that came into contact at some update (a
    /// contact pushed them apart, or their surfaces came within [`TOUCH_TOLERANCE`]).
    pub collided: BTreeSet<(usize, usize)>,
    /// The pairs whose surfaces are within [`TOUCH_TOLERANCE`] at the end.
    pub touching: BTreeSet<(usize, usize)>,
    /// The cloth's particles at the end.
    pub cloth_end: Vec<Vector>,
    /// Solver updates taken.
    pub updates: usize,
}

/// The mass assumed for a box of `shape` under a cloth of friction `friction`, kg (see the
/// module's doc): the heaviest of its pool where nothing moved it (`undisturbed`), the lightest
/// otherwise.
pub fn assumed_mass(shape: Shape, friction: Option<Friction>, undisturbed: bool) -> f64 {
    let pick = |friction: Friction| {
        let (plates, pillars) = mass_pools(friction);
        let pool = if shape == Shape::Plate {
            plates
        } else {
            pillars
        };
        if undisturbed {
            pool.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        } else {
            pool.iter().copied().fold(f64::INFINITY, f64::min)
        }
    };
    match friction {
        Some(friction) => pick(friction),
        None => f64::midpoint(pick(Friction::Low), pick(Friction::High)),
    }
}

/// The orientation of Unity Euler angles (degrees: turns about z, then x, then y).
pub fn unity_rotation(euler_degrees: [f64; 3]) -> Quaternion {
    let about = |axis: usize, degrees: f64| {
        let half = degrees.to_radians() / 2.0;
        let mut turn = [half.cos(), 0.0, 0.0, 0.0];
        turn[axis + 1] = half.sin();
        turn
    };
    let [x, y, z] = euler_degrees;
    v3::quaternion_product(
        v3::quaternion_product(about(1, y), about(0, x)),
        about(2, z),
    )
}

/// Simulates `half` under `model` to the release's end update.
pub fn simulate_half(half: &SeenHalf, model: &ClothModel) -> Result<HalfRun, SimulationError> {
    let cloth = &half.cloth;
    if cloth.spawn.len() < 4 {
        return Err(SimulationError::Cloth(format!(
            "has {} particles",
            cloth.spawn.len()
        )));
    }
    if let Some(bad) = cloth
        .spawn
        .iter()
        .position(|p| !p.iter().all(|v| v.is_finite()))
    {
        return Err(SimulationError::Cloth(format!(
            "has a non-finite position (particle {bad})"
        )));
    }
    let settings = XpbdSettings {
        substeps: model.substeps,
        iterations: model.iterations,
        ..XpbdSettings::default()
    };
    let mut world = World::new(settings)?;
    for seen in &half.boxes {
        world.add_box(BoxBody::new(
            v3::scale(seen.size, 0.5),
            seen.mass
                .unwrap_or_else(|| assumed_mass(seen.shape, half.cloth.friction, seen.undisturbed)),
            seen.position,
            seen.orientation,
        ))?;
    }
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a pull of about 5 units at 3 units/s is about 100 updates; clamped to the run"
    )]
    let pull_updates = (half.cloth.pull_distance.max(0.0) / PULL_SPEED * 60.0)
        .round()
        .min(1e6) as usize;
    let mut collided = BTreeSet::new();
    for update in 1..=END_UPDATE {
        if update == SPAWN_UPDATE {
            let mut sheet = spawn_sheet(&half.cloth, model);
            sheet.grip_front_edge();
            sheet.set_handle_velocity([0.0, 0.0, PULL_SPEED]);
            world.add_sheet(sheet);
        }
        if let Some(sheet) = world.sheet_mut(0) {
            if update == SPAWN_UPDATE + pull_updates {
                sheet.set_handle_velocity([0.0; 3]);
            }
            if update == RELEASE_UPDATE {
                sheet.release();
            }
        }
        let contacts = world.step()?;
        collided.extend(contacts.box_pairs.iter().copied());
        collided.extend(world.box_pairs_within(TOUCH_TOLERANCE));
    }
    let (end_poses, end_states) = world
        .boxes()
        .iter()
        .map(|body| {
            let up = v3::apply(body.rotation(), [0.0, 1.0, 0.0]);
            (Pose::from_up_axis(up), (body.position, body.orientation))
        })
        .unzip();
    Ok(HalfRun {
        end_poses,
        end_states,
        collided,
        touching: world.box_pairs_within(TOUCH_TOLERANCE),
        cloth_end: world
            .sheets()
            .first()
            .map_or_else(Vec::new, |sheet| sheet.positions().to_vec()),
        updates: END_UPDATE,
    })
}

/// The cloth as it spawns, at the model's resolution over the seen cloth's extent.
fn spawn_sheet(cloth: &SeenCloth, model: &ClothModel) -> Sheet {
    let (mut low, mut high) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for point in &cloth.spawn {
        for axis in 0..3 {
            low[axis] = low[axis].min(point[axis]);
            high[axis] = high[axis].max(point[axis]);
        }
    }
    let side = f64::midpoint(high[0] - low[0], high[2] - low[2]);
    let height = f64::midpoint(low[1], high[1]);
    let resolution = model.resolution.max(2);
    let spacing = side / (resolution - 1) as f64;
    let [high_friction, low_friction] = VALUES.friction;
    let friction = match cloth.friction {
        Some(Friction::Low) => low_friction,
        Some(Friction::High) => high_friction,
        None => f64::midpoint(low_friction, high_friction),
    };
    // A bend triplet's middle particle may leave the centroid by the max bending d, which on a
    // grid of spacing h allows a curvature of 3d/h²: a coarser grid keeps the video cloth's
    // curvature with d scaled by the square of the spacings' ratio.
    let spacing_ratio = (CLOTH_RESOLUTION - 1) as f64 / (resolution - 1) as f64;
    Sheet::new(&SheetSpec {
        resolution,
        side,
        corner: [low[0], height, low[2]],
        mass: CLOTH_AREAL_MASS * side * side,
        particle_radius: model.radius_per_spacing * spacing,
        properties: SheetProperties {
            stretch_compliance: cloth.stretch_compliance,
            max_bending: cloth.max_bending * spacing_ratio * spacing_ratio,
            friction: model.friction_scale * f64::midpoint(friction, OBJECT_FRICTION),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::vector3::rotation_matrix;
    use crate::synth::unity::unity_euler_degrees;

    /// A flat 31 × 31 cloth of side 3 at `height`, its far edge at z = −3.4, over x ∈ [−1.5, 1.5].
    fn spawn(height: f64) -> Vec<Vector> {
        (0..31 * 31_u32)
            .map(|k| {
                let (column, row) = (f64::from(k % 31), f64::from(k / 31));
                [-1.5 + 0.1 * column, height, -6.4 + 0.1 * row]
            })
            .collect()
    }

    fn upright(name: &str, shape: Shape, size: Vector, x: f64, z: f64) -> SeenBox {
        SeenBox {
            name: name.to_string(),
            shape,
            size,
            position: [x, size[1] / 2.0, z],
            orientation: [1.0, 0.0, 0.0, 0.0],
            mass: None,
            undisturbed: false,
        }
    }

    #[test]
    fn unity_angles_turn_back_into_the_rotation_they_were_read_from() {
        for euler in [[0.0, 17.0, 0.0], [20.0, 130.0, 300.0], [350.0, 5.0, 91.0]] {
            let read = unity_euler_degrees(&rotation_matrix(unity_rotation(euler)));
            for (found, expected) in read.iter().zip(euler) {
                assert!(
                    (found - expected).abs() < 1e-9,
                    "{euler:?} read back as {read:?}"
                );
            }
        }
    }

    #[test]
    fn assumed_masses_are_the_pool_s_movable_mass_or_its_immovable_one_where_nothing_moved_it() {
        let masses = [
            assumed_mass(Shape::Plate, Some(Friction::Low), false),
            assumed_mass(Shape::Pillar, Some(Friction::High), false),
            assumed_mass(Shape::Pillar, None, false),
            assumed_mass(Shape::Plate, None, true),
        ];
        assert_eq!(
            masses.map(f64::to_bits),
            [2.0, 12.0, 9.25, 99999.0].map(f64::to_bits)
        );
    }

    #[test]
    fn stiff_and_extreme_halves_stay_finite_and_give_a_pose_for_every_box() {
        // At the inference setting: a cloth that neither stretches nor bends, dragged 30 units
        // (six times the release's pull, through the table's far side), over a light plate, a
        // pillar leaning at 40° and a plate spawned into the cloth; then the stretchiest and
        // floppiest cloth the release draws, not pulled at all.
        let mut leaning = upright("Gray Pillar", Shape::Pillar, [0.5, 2.2, 0.5], -0.6, -1.0);
        leaning.orientation = unity_rotation([40.0, 0.0, 0.0]);
        leaning.position[1] = 1.0;
        let mut inside = upright("Green Plate", Shape::Plate, [1.2, 1.8, 0.4], 0.6, -0.2);
        inside.position[1] = 2.2;
        let boxes = vec![
            upright("Blue Plate", Shape::Plate, [1.0, 1.5, 0.35], 0.0, 0.3),
            leaning,
            inside,
        ];
        let cases = [
            SeenCloth {
                spawn: spawn(2.5),
                stretch_compliance: 0.0,
                max_bending: 0.0,
                friction: Some(Friction::High),
                pull_distance: 30.0,
            },
            SeenCloth {
                spawn: spawn(2.4),
                stretch_compliance: 0.011,
                max_bending: 0.035,
                friction: None,
                pull_distance: 0.0,
            },
        ];
        for cloth in cases {
            let half = SeenHalf {
                boxes: boxes.clone(),
                cloth,
            };
            let run = simulate_half(&half, &ClothModel::default()).unwrap();
            assert_eq!(run.end_poses.len(), 3);
            for (position, orientation) in &run.end_states {
                assert!(position.iter().chain(orientation).all(|v| v.is_finite()));
                // Nothing leaves the table's neighbourhood or sinks through it.
                assert!(position[1] > -0.05 && position[1] < 5.0, "{position:?}");
            }
            assert!(
                run.cloth_end
                    .iter()
                    .flatten()
                    .all(|v| v.is_finite() && v.abs() < 100.0)
            );
        }
    }

    #[test]
    fn a_cloth_that_is_not_finite_is_an_error_not_an_answer() {
        let mut cloth_spawn = spawn(2.4);
        cloth_spawn[100][1] = f64::NAN;
        let half = SeenHalf {
            boxes: vec![upright(
                "Blue Plate",
                Shape::Plate,
                [1.0, 1.5, 0.35],
                0.0,
                0.3,
            )],
            cloth: SeenCloth {
                spawn: cloth_spawn,
                stretch_compliance: 0.0,
                max_bending: 0.013,
                friction: None,
                pull_distance: 5.0,
            },
        };
        let error = simulate_half(&half, &ClothModel::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the cloth seen at the spawn has a non-finite position (particle 100)"
        );
    }
}
