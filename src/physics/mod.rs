//! Physics simulators, in f64 with SI units (metres, kilograms, seconds): what `--dynamics
//! simulate` answers from instead of the annotations.
//!
//! Input: a mechanism described by the scene layer (bodies, pulleys, ropes), and for
//! identification observed heights over time. Output: states over time, constraint forces,
//! ranked mass candidates with verdicts, and typed errors for what cannot be simulated. Layer 1
//! (`docs/architecture.md`, layers): uses only `util`.
//!
//! * [`rope`]: rope–pulley networks (ideal inextensible ropes that only pull, pulley inertia,
//!   Coulomb bearing friction, floor and pulley stops), one complementarity problem per step;
//!   [`rope::identify`] infers load masses from observed motion.
//! * [`fluid`]: 2D position-based fluids, the fluid scenario's truth solver (the release's Obi
//!   Fluid settings).
//! * [`shape_matching`]: particle soft bodies held by shape matching, the ball scenario's truth
//!   solver (the release's Obi Softbody settings).
//! * [`mpm`]: 2D MLS-MPM (core plus materials), ContPRO's simulator for fluids and balls.
//! * [`xpbd`]: XPBD cloth two-way coupled with rigid boxes, the cloth scenario's truth solver
//!   (the release's Obi Cloth and PhysX settings).
//! * [`linalg`]: the small dense solvers they share; [`slab`]: the slabs' signed distance;
//!   [`vector3`]: 3-vectors, 3 × 3 matrices and quaternions.
//! * [`bench`](mod@bench): what each simulator brings to `bench physics` (cases with known
//!   answers).

pub mod bench;
pub mod fluid;
pub mod linalg;
pub mod mpm;
pub mod rope;
pub mod shape_matching;
pub mod slab;
pub mod vector3;
pub mod xpbd;
