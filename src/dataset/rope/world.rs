//! Facts of the release's rope world that answers and simulations depend on: the timeline and
//! thresholds of `ResultMotion`/`ResultRotation` (the rope data format, `docs/data/rope.md`) and
//! the prefabs' sizes and masses (read from the generator's prefabs; the pulley inertia is checked
//! against the real video, whose loads move as 1 kg disc pulleys predict). Units: world units
//! (nominally metres), kilograms, seconds.

/// One physics update of the generator, s (60 Hz); frames are taken every second update.
pub const UPDATE_SECONDS: f64 = 1.0 / 60.0;
/// Updates from one captured frame (video frame, 4-D record) to the next.
pub const UPDATES_PER_FRAME: u32 = 2;
/// The update at which the factual run applies its random masses and starts recording
/// (and counterfactual runs make their change).
pub const CHANGE_UPDATE: u32 = 100;
/// Updates a factual run simulates after the change (the video's 300 plus 200 unseen).
pub const FACTUAL_UPDATES_AFTER_CHANGE: u32 = 500;
/// Updates a counterfactual run simulates after its change.
pub const COUNTERFACTUAL_UPDATES_AFTER_CHANGE: u32 = 300;
/// Vertical travel from the change that counts as motion, units.
pub const MOTION_THRESHOLD: f64 = 1.2;
/// Turn from the change that counts as rotation, degrees.
pub const ROTATION_THRESHOLD_DEG: f64 = 35.0;
/// The masses a factual run draws each load's from, kg, in the generator's order (times
/// the load's multiplier).
pub const LOAD_MASSES_KG: [f64; 3] = [0.15, 0.25, 0.20];
/// Every load's mass in counterfactual runs (and before the change), kg, times its
/// multiplier.
pub const BASELINE_MASS_KG: f64 = 0.2;
/// A counterfactual run's mass change, kg, times the load's multiplier (lighter: −).
pub const COUNTERFACTUAL_MASS_STEP_KG: f64 = 0.1;
/// Mass multiplier of a load hanging under a movable pulley.
pub const MOVABLE_PULLEY_LOAD_MULTIPLIER: f64 = 1.975;
/// Speed of a pulled static pulley or fixed point, units/s.
pub const PULL_SPEED: f64 = 2.0;
/// How far a pulled static pulley moves, units.
pub const PULL_PULLEY_DISTANCE: f64 = 3.5;
/// How far a pulled fixed point moves, units.
pub const PULL_ANCHOR_DISTANCE: f64 = 7.0;
/// Mass of a static pulley's disc, kg (it turns about its axle).
pub const STATIC_PULLEY_KG: f64 = 1.0;
/// Mass of a movable pulley, kg.
pub const MOVABLE_PULLEY_KG: f64 = 0.005;
/// How far below a movable pulley's axle the load on its connection rope hangs (centre to
/// centre), units.
pub const CONNECTION_DROP: f64 = 4.0;
/// Disc radius of a solid ("little") pulley, units.
pub const SOLID_PULLEY_RADIUS: f64 = 1.74;
/// Disc radius of a hollow ("big") pulley, units.
pub const HOLLOW_PULLEY_RADIUS: f64 = 1.613;
/// Radius at which the rope wraps a solid pulley, units.
pub const SOLID_WRAP_RADIUS: f64 = 1.914;
/// Radius at which the rope wraps a hollow pulley, units.
pub const HOLLOW_WRAP_RADIUS: f64 = 1.61;
/// Horizontal offset of an end load or anchor from its pulley's centre in the layout
/// (`metaSamplingData.name2position`), units.
pub const LAYOUT_END_OFFSET: f64 = 1.48;
/// Half the height of a load (cube side 2, sphere diameter 2), units.
pub const LOAD_HALF_HEIGHT: f64 = 1.0;
/// Height of a load's rope attachment above its centre, units.
pub const LOAD_ATTACH_HEIGHT: f64 = 0.8;
/// Height of a fixed point's rope attachment above its centre, units.
pub const ANCHOR_ATTACH_HEIGHT: f64 = 0.28;
/// Rope radius, units.
pub const ROPE_RADIUS: f64 = 0.2;

/// Moment of inertia of a static pulley's disc about its axle, kg·m²: a uniform disc,
/// `½ m r²`.
pub fn static_pulley_inertia(solid: bool) -> f64 {
    let radius = if solid {
        SOLID_PULLEY_RADIUS
    } else {
        HOLLOW_PULLEY_RADIUS
    };
    0.5 * STATIC_PULLEY_KG * radius * radius
}

/// The rope's wrap radius round a pulley, units.
pub fn wrap_radius(solid: bool) -> f64 {
    if solid {
        SOLID_WRAP_RADIUS
    } else {
        HOLLOW_WRAP_RADIUS
    }
}
