//! One half of a cloth scene through the release's timeline, on the XPBD truth solver
//! (`physics::xpbd`): the boxes stand from update 0; the cloth spawns flat at update 60, gripped
//! along its far edge, and is dragged along +z at 3 units/s for its pull distance; the handle
//! holds still until it lets go at update 190; the end state is read at update 288 and the run
//! stops at 290 (updates of 1/60 s).
//!
//! Outputs per box what the release records (`docs/data/cloth.md`): collision events (a contact
//! with another box or the cloth beginning, with its update; the table is not recorded, as the
//! release leaves out the floor), the first update it moves faster than 0.2 units/s or turns
//! faster than 0.2 rad/s, what it touches at update 288 (the cloth if it touched it within the
//! last two updates), and its end pose; per captured update (every second one, 0 to 288) the
//! boxes' poses and the cloth's particles; the cloth's mean stretch force per quadrant at the
//! last update.

use crate::physics::vector3::{Quaternion, Vector, norm};
use crate::physics::xpbd::{
    BoxBody, Sheet, SheetProperties, SheetSpec, UpdateContacts, World, XpbdError, XpbdSettings,
};

use super::layout::{
    CLOTH_HEIGHT, CLOTH_RESOLUTION, CLOTH_SIDE, CLOTH_START_Z, ClothLayout, HalfLayout,
};

/// The update the cloth spawns at.
pub const SPAWN_UPDATE: usize = 60;
/// The update the handle lets go.
pub const RELEASE_UPDATE: usize = 190;
/// The update the end state is read at.
pub const END_UPDATE: usize = 288;
/// The last update simulated.
pub const LAST_UPDATE: usize = 290;
/// Updates per captured frame.
pub const CAPTURE_EVERY: usize = 2;
/// The handle's speed, units/s.
pub const PULL_SPEED: f64 = 3.0;
/// Speed (units/s) or angular speed (rad/s) above which a box counts as moving.
const MOVING: f64 = 0.2;
/// Mass of a cloth per unit area, kg/m² (the release does not record it).
pub const CLOTH_AREAL_MASS: f64 = 0.1;
/// The friction of the table, plates and pillars (`HighFriction`), averaged with the cloth's
/// as Unity and Obi combine frictions by default.
pub const OBJECT_FRICTION: f64 = 4.0;
/// A cloth particle's radius per grid spacing.
pub const RADIUS_PER_SPACING: f64 = 0.4;

/// The cloth's friction in this solver per unit of the release's coefficient. The release's
/// values (0.5 or 4 for the cloth, 4 for the objects, averaged) are Obi solver settings, not
/// coefficients a converged Coulomb contact can take as they are: a cloth wrapped over a box's
/// edge grips by the capstan effect, e^(μθ), a factor of 500 at μ = 4 over a right angle, and
/// under the kinematic handle it carried 6.5–12-kg pillars into the air. With the boxes' edges
/// colliding with the cloth's triangles (`physics::xpbd::box_edges`), over the first 16 videos
/// of seed 2026 (93 boxes), boxes risen more than 0.3 units / ended upright: 15 / 35 unscaled,
/// 2 / 40 at 0.5, 0 / 51 at 0.25. 0.5 nearly stops the carrying while the boxes fall nearly as
/// often as unscaled (`docs/data/cloth.md`, *Carried boxes*).
pub const FRICTION_SCALE: f64 = 0.5;

/// What one box did.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxOutcome {
    /// Contacts beginning: (update, the other's name), by time.
    pub collisions: Vec<(u32, String)>,
    /// The first update it moved, if it did.
    pub start_moving: Option<u32>,
    /// Names it touches at the end.
    pub touchers: Vec<String>,
    /// Its centre at the end, units.
    pub end_position: Vector,
    /// Its orientation at the end.
    pub end_orientation: Quaternion,
}

/// A captured update.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfFrame {
    /// Each box's centre and orientation.
    pub boxes: Vec<(Vector, Quaternion)>,
    /// The cloth's particles, once it has spawned.
    pub cloth: Option<Vec<Vector>>,
}

/// A simulated half.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfRun {
    /// Captured updates 0, 2, …, 288.
    pub frames: Vec<HalfFrame>,
    /// Per box of the layout.
    pub outcomes: Vec<BoxOutcome>,
    /// Mean stretch force per quadrant at the last update, N (quadrants 1 to 4).
    pub region_forces: [f64; 4],
    /// The cloth mesh's triangles.
    pub triangles: Vec<[usize; 3]>,
    /// Solver updates taken.
    pub updates: usize,
}

/// The box of a layout entry at rest on the table (y = 0).
pub fn box_body(half: &HalfLayout, index: usize) -> Option<BoxBody> {
    let entry = half.boxes.get(index)?;
    let half_yaw = entry.yaw_degrees.to_radians() / 2.0;
    Some(BoxBody::new(
        entry.size.map(|s| s / 2.0),
        entry.mass,
        [
            half.centre_x + entry.footprint[0],
            entry.size[1] / 2.0,
            entry.footprint[1],
        ],
        [half_yaw.cos(), 0.0, half_yaw.sin(), 0.0],
    ))
}

/// The cloth of a half as it spawns.
pub fn spawn_sheet(half: &HalfLayout) -> Sheet {
    let cloth: &ClothLayout = &half.cloth;
    let spacing = CLOTH_SIDE / (CLOTH_RESOLUTION - 1) as f64;
    Sheet::new(&SheetSpec {
        resolution: CLOTH_RESOLUTION,
        side: CLOTH_SIDE,
        corner: [
            half.centre_x - CLOTH_SIDE / 2.0,
            CLOTH_HEIGHT + cloth.height_offset,
            CLOTH_START_Z - CLOTH_SIDE,
        ],
        mass: CLOTH_AREAL_MASS * CLOTH_SIDE * CLOTH_SIDE,
        particle_radius: RADIUS_PER_SPACING * spacing,
        properties: SheetProperties {
            stretch_compliance: cloth.stretch_compliance,
            max_bending: cloth.max_bending,
            friction: FRICTION_SCALE * f64::midpoint(cloth.friction_coefficient(), OBJECT_FRICTION),
        },
    })
}

/// Runs one half through the release's timeline.
pub fn run_half(half: &HalfLayout) -> Result<HalfRun, XpbdError> {
    let mut world = World::new(XpbdSettings::default())?;
    for index in 0..half.boxes.len() {
        if let Some(body) = box_body(half, index) {
            world.add_box(body)?;
        }
    }
    let names: Vec<&str> = half.boxes.iter().map(|b| b.name.as_str()).collect();
    let cloth_name = half.side.cloth_name();
    let count = names.len();
    let mut outcomes: Vec<BoxOutcome> = (0..count)
        .map(|_| BoxOutcome {
            collisions: Vec::new(),
            start_moving: None,
            touchers: Vec::new(),
            end_position: [0.0; 3],
            end_orientation: [1.0, 0.0, 0.0, 0.0],
        })
        .collect();
    let mut frames = vec![capture(&world)];
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a pull of about 5 units at 3 units/s is about 100 updates"
    )]
    let pull_updates = (half.cloth.pull_distance / PULL_SPEED * 60.0).round() as usize;
    let mut previous = UpdateContacts::default();
    let mut cloth_touched_at = vec![None::<usize>; count];
    for update in 1..=LAST_UPDATE {
        if update == SPAWN_UPDATE {
            let mut sheet = spawn_sheet(half);
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
        let stamp = u32::try_from(update).unwrap_or(u32::MAX);
        for &(a, b) in contacts.box_pairs.difference(&previous.box_pairs) {
            outcomes[a].collisions.push((stamp, names[b].to_string()));
            outcomes[b].collisions.push((stamp, names[a].to_string()));
        }
        for &(_, body) in contacts.sheet_boxes.difference(&previous.sheet_boxes) {
            outcomes[body]
                .collisions
                .push((stamp, cloth_name.to_string()));
        }
        for &(_, body) in &contacts.sheet_boxes {
            cloth_touched_at[body] = Some(update);
        }
        for (outcome, body) in outcomes.iter_mut().zip(world.boxes()) {
            let (speed, spin) = (norm(body.velocity), norm(body.angular_velocity));
            if outcome.start_moving.is_none() && (speed > MOVING || spin > MOVING) {
                outcome.start_moving = Some(stamp);
            }
        }
        if update == END_UPDATE {
            for (index, outcome) in outcomes.iter_mut().enumerate() {
                for &(a, b) in &contacts.box_pairs {
                    if a == index {
                        outcome.touchers.push(names[b].to_string());
                    } else if b == index {
                        outcome.touchers.push(names[a].to_string());
                    }
                }
                if cloth_touched_at[index].is_some_and(|at| at + 2 > END_UPDATE) {
                    outcome.touchers.push(cloth_name.to_string());
                }
                let body = &world.boxes()[index];
                outcome.end_position = body.position;
                outcome.end_orientation = body.orientation;
            }
        }
        if update % CAPTURE_EVERY == 0 && update <= END_UPDATE {
            frames.push(capture(&world));
        }
        previous = contacts;
    }
    let sheet = world.sheets().first();
    Ok(HalfRun {
        frames,
        outcomes,
        region_forces: sheet.map_or([0.0; 4], |s| s.quadrant_forces(world.substep_seconds())),
        triangles: sheet.map_or_else(Vec::new, |s| s.triangles().to_vec()),
        updates: LAST_UPDATE,
    })
}

/// The world's state as a frame records it.
fn capture(world: &World) -> HalfFrame {
    HalfFrame {
        boxes: world
            .boxes()
            .iter()
            .map(|body| (body.position, body.orientation))
            .collect(),
        cloth: world.sheets().first().map(|s| s.positions().to_vec()),
    }
}
