//! Facts of the release's fluid world that its annotations and answers depend on
//! (`docs/data/fluid.md`, read from the generator's `FluidSlidesConfig`): the timeline, the
//! particle-count thresholds of `trackingData`, the counterfactual stick choice, and the sampled
//! fluid properties. Units: world units (nominally metres), updates of [`UPDATE_SECONDS`].

/// One physics update, s (the release's `simDeltaTime` 0.0166, nominally 1/60 s).
pub const UPDATE_SECONDS: f64 = 1.0 / 60.0;
/// Updates from one captured frame (video frame, 4-D record) to the next.
pub const UPDATES_PER_FRAME: u32 = 2;
/// The update at which the factual emitters open.
pub const EMITTER_OPEN_UPDATE: u32 = 2;
/// The update at which predictive emitters (`Later Emitted …`) open: 40 updates before the
/// capture ends, about 20 frames before the end of the video.
pub const PREDICTIVE_EMITTER_OPEN_UPDATE: u32 = 460;
/// The update at which capture stops (250 sensor frames).
pub const CAPTURE_UPDATES: u32 = 500;
/// Updates of a factual run: `trackingData` is taken after them, so it includes 200 updates the
/// video does not show.
pub const FACTUAL_UPDATES: u32 = 700;
/// Updates of a counterfactual run (factual emitters only, nothing recorded visually).
pub const COUNTERFACTUAL_UPDATES: u32 = 500;

/// A collider is listed in `perEmitterStickStat` when more than this many of a fluid's particles
/// touched it (`collide_particle_num_to_be_valid`); a regular stick over it is also
/// "temperature askable".
pub const CONTACT_MIN_PARTICLES: u32 = 20;
/// A fluid is listed in a container's `perReceptorFluidStat` when more than this many of its
/// particles end inside (`receptor_particle_num_to_be_valid`).
pub const RECEPTOR_MIN_PARTICLES: u32 = 20;
/// A stick is a counterfactual candidate of a fluid when more than this many of its particles
/// touched it (`min_pass_particles`).
pub const COUNTERFACTUAL_MIN_PASS_PARTICLES: u32 = 100;
/// Candidate sticks per fluid: its two most touched regular sticks.
pub const COUNTERFACTUAL_STICKS_PER_FLUID: usize = 2;
/// At most this many sticks get a counterfactual run (`max_cf_remove`).
pub const COUNTERFACTUAL_MAX_REMOVED_STICKS: usize = 6;

/// Particles per emitter (`fluid_ptk_amount_total`), the `amount` of every fluid.
pub const PARTICLES_PER_EMITTER: u32 = 1500;
/// Density pool of a 3-fluid video, each value used once (kg/m³ as Obi rest density).
pub const DENSITIES_3_FLUIDS: [f64; 3] = [1600.0, 3000.0, 4400.0];
/// Density pool of a 4-fluid video.
pub const DENSITIES_4_FLUIDS: [f64; 4] = [1200.0, 2600.0, 4000.0, 5400.0];
/// Obi viscosity of a `"Sticky"` fluid.
pub const STICKY_VISCOSITY: f64 = 10.0;
/// Obi viscosity of a `"Non-Sticky"` fluid.
pub const NON_STICKY_VISCOSITY: f64 = 0.02;
/// Every stick's temperature in the release (its icy/boiling fraction is 0).
pub const NORMAL_TEMPERATURE: &str = "Normal";
/// The tank's inner size (x, y, z), units.
pub const TANK_SIZE: [f64; 3] = [5.0, 2.5, 1.0];
/// Colour ids fluids draw from (Orange, Yellow, Green, Cyan, Blue, Pink, Light Blue).
pub const FLUID_COLOR_IDS: [u8; 7] = [1, 2, 3, 4, 5, 7, 12];
/// Colour ids sticks and containers draw from (White, Red, Black, Orange, Yellow, Green, Cyan,
/// Blue, Purple, Pink, Brown, Gray).
pub const STICK_COLOR_IDS: [u8; 12] = [11, 0, 10, 1, 2, 3, 4, 5, 6, 7, 8, 9];
