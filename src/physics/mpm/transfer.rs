//! The per-particle kernels of the substep: the quadratic B-spline stencil, particle to tile
//! (scatter), grid to particle (gather) and the per-particle checks after it.
//!
//! These run once per particle per substep and dominate the solver's time, so they are written
//! for the optimiser: fixed-size arrays, one bounds check per stencil row, products that do not
//! depend on the inner index hoisted out of it. Hoisting only reuses a product; every sum keeps
//! the order of the plain formula, so the bytes do not depend on how the loops are written.

use super::material::Material;
use super::solver::ParticleState;

/// Nodes along each side of a block: the unit of binning and of parallel scattering.
pub(super) const BLOCK: usize = 8;
/// A block's private tile: its nodes plus the two the quadratic stencil reaches beyond.
pub(super) const TILE: usize = BLOCK + 2;

/// What does not move: a particle's constants.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct ParticleConstants {
    pub(super) mass: f64,
    pub(super) volume: f64,
    pub(super) material: u32,
    pub(super) id: u32,
}

/// The numbers every particle of one substep shares.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepConstants {
    pub(super) origin: [f64; 2],
    pub(super) dx: f64,
    pub(super) inverse: f64,
    pub(super) dt: f64,
}

impl StepConstants {
    /// The particle's stencil from its base node (low corner, from [`Self::base_cell`]): the
    /// base as indices, its weights along each axis, and its fractional offset in cells.
    #[inline]
    fn stencil(&self, position: [f64; 2], base: [u32; 2]) -> ([usize; 2], [[f64; 3]; 2], [f64; 2]) {
        let scaled = [
            (position[0] - self.origin[0]) * self.inverse,
            (position[1] - self.origin[1]) * self.inverse,
        ];
        let fx = [
            scaled[0] - f64::from(base[0]),
            scaled[1] - f64::from(base[1]),
        ];
        let base = [base[0] as usize, base[1] as usize];
        (base, [weights(fx[0]), weights(fx[1])], fx)
    }

    /// The node at the low corner of a particle's 3 × 3 stencil, `⌊x/dx − 1/2⌋` per axis. The
    /// gather computes it once for the new position; the next scatter and gather reuse it, which
    /// saves the float to integer and back conversions at the head of their dependency chains.
    #[inline]
    pub(super) fn base_cell(&self, position: [f64; 2]) -> [u32; 2] {
        let x = (position[0] - self.origin[0]) * self.inverse - 0.5;
        let y = (position[1] - self.origin[1]) * self.inverse - 0.5;
        [cell_floor(x), cell_floor(y)]
    }

    /// Index of the grid node nearest to `position` (clamped positions keep it in the grid).
    #[inline]
    pub(super) fn nearest_node(&self, position: [f64; 2], columns: usize) -> usize {
        let i = grid_index(((position[0] - self.origin[0]) * self.inverse).round());
        let j = grid_index(((position[1] - self.origin[1]) * self.inverse).round());
        i * columns + j
    }
}

/// A grid coordinate (in cells) as a node index. Positions are clamped into the grid, so it is
/// ≥ 0 and small. `as` truncates toward zero and saturates, which for any input equals `floor`
/// then `as` (the textbook formula's index) without the call to `floor` the baseline x86-64
/// target makes.
#[inline]
#[expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "clamped positions give small non-negative cell coordinates; as saturates"
)]
pub(super) fn grid_index(cells: f64) -> usize {
    cells as usize
}

/// `⌊cells⌋` for the stencil, at least 0: truncation equals the floor for the non-negative
/// coordinates of clamped positions, and negatives (never reached) saturate to 0 as `floor` then
/// `as usize` did. `i32` keeps the conversion one instruction (`usize` needs a fix-up for the
/// top bit); grids have at most 2¹⁵ nodes a side.
#[inline]
#[expect(
    clippy::cast_possible_truncation,
    reason = "clamped positions give small non-negative cell coordinates; as saturates"
)]
fn cell_floor(cells: f64) -> u32 {
    (cells as i32).max(0).unsigned_abs()
}

/// Quadratic B-spline weights along one axis for fractional offset `fx ∈ [0.5, 1.5)`.
#[inline]
fn weights(fx: f64) -> [f64; 3] {
    [
        0.5 * (1.5 - fx) * (1.5 - fx),
        0.75 - (fx - 1.0) * (fx - 1.0),
        0.5 * (fx - 0.5) * (fx - 0.5),
    ]
}

/// Adds one particle's mass, momentum and stress to its block's tile, whose low corner is node
/// `corner` (the particle's base node `base` lies in the block).
#[inline]
pub(super) fn scatter_particle(
    tile: &mut [[f64; 3]],
    corner: [usize; 2],
    particle: &ParticleState,
    base: [u32; 2],
    constant: &ParticleConstants,
    material: &Material,
    step: &StepConstants,
) {
    let (base, w, fx) = step.stencil(particle.position, base);
    let dx = step.dx;
    let stress = material.kirchhoff_stress(
        particle.volume_ratio,
        &particle.deformation,
        &particle.affine,
    );
    let scale = -step.dt * 4.0 * constant.volume * step.inverse * step.inverse;
    let mass = constant.mass;
    let affine = [
        scale * stress[0] + mass * particle.affine[0],
        scale * stress[1] + mass * particle.affine[1],
        scale * stress[2] + mass * particle.affine[2],
        scale * stress[3] + mass * particle.affine[3],
    ];
    let momentum = [mass * particle.velocity[0], mass * particle.velocity[1]];
    // `affine · dpos` split into its x and y products, each computed once, as lanes (x, y) of
    // the node's momentum so the optimiser can pair them.
    let dpos_y = [(0.0 - fx[1]) * dx, (1.0 - fx[1]) * dx, (2.0 - fx[1]) * dx];
    let affine_y = dpos_y.map(|d| [affine[1] * d, affine[3] * d]);
    let local = [
        base[0].wrapping_sub(corner[0]),
        base[1].wrapping_sub(corner[1]),
    ];
    for (i, wi) in w[0].iter().enumerate() {
        let dpos_x = (i as f64 - fx[0]) * dx;
        let affine_x = [affine[0] * dpos_x, affine[2] * dpos_x];
        let start = (local[0] + i) * TILE + local[1];
        // The particle's base node is in the block, so the row is in the tile; a miss (only
        // possible for a particle outside its block, a bug) drops the row rather than panic.
        let Some(row) = tile.get_mut(start..start + 3) else {
            continue;
        };
        for ((node, wj), affine_y) in row.iter_mut().zip(w[1]).zip(affine_y) {
            let weight = wi * wj;
            for lane in 0..2 {
                node[lane] += weight * (momentum[lane] + (affine_x[lane] + affine_y[lane]));
            }
            node[2] += weight * mass;
        }
    }
}

/// Grid to particle: velocity, APIC matrix, position and volume ratio from the 3 × 3 stencil of
/// node velocities (`[vx, vy, mass]`, row-major with `columns` nodes a row).
#[inline]
pub(super) fn gather_particle(
    particle: &mut ParticleState,
    base: [u32; 2],
    nodes: &[[f64; 3]],
    columns: usize,
    step: &StepConstants,
) {
    let (base, w, fx) = step.stencil(particle.position, base);
    let dx = step.dx;
    let dpos_y = [(0.0 - fx[1]) * dx, (1.0 - fx[1]) * dx, (2.0 - fx[1]) * dx];
    // Lanes (x, y) of the node velocity: `velocity`, and the APIC sums `Σ w·v·dpos_x`
    // (`affine_x`) and `Σ w·v·dpos_y` (`affine_y`), each summed in stencil order.
    let mut velocity = [0.0; 2];
    let mut affine_x = [0.0; 2];
    let mut affine_y = [0.0; 2];
    for (i, wi) in w[0].iter().enumerate() {
        let dpos_x = (i as f64 - fx[0]) * dx;
        let start = (base[0] + i) * columns + base[1];
        // Positions are clamped so the stencil is in the grid; a miss contributes nothing.
        let Some(row) = nodes.get(start..start + 3) else {
            continue;
        };
        for ((node, wj), dpos_y) in row.iter().zip(w[1]).zip(dpos_y) {
            let weight = wi * wj;
            let scaled_weight = 4.0 * weight;
            for lane in 0..2 {
                velocity[lane] += weight * node[lane];
                affine_x[lane] += scaled_weight * node[lane] * dpos_x;
                affine_y[lane] += scaled_weight * node[lane] * dpos_y;
            }
        }
    }
    let mut affine = [affine_x[0], affine_y[0], affine_x[1], affine_y[1]];
    let inverse_squared = step.inverse * step.inverse;
    for value in &mut affine {
        *value *= inverse_squared;
    }
    particle.velocity = velocity;
    particle.position[0] += step.dt * velocity[0];
    particle.position[1] += step.dt * velocity[1];
    particle.volume_ratio *= 1.0 + step.dt * (affine[0] + affine[3]);
    particle.affine = affine;
}

/// Squared speed (the maximum's square root is taken once: `sqrt` is monotonic and correctly
/// rounded, so it is the same number as the maximum of the square roots).
#[inline]
pub(super) fn speed_squared(state: &ParticleState) -> f64 {
    state.velocity[0] * state.velocity[0] + state.velocity[1] * state.velocity[1]
}

/// Squared Frobenius norm of the APIC matrix (see [`speed_squared`]).
#[inline]
pub(super) fn affine_norm_squared(state: &ParticleState) -> f64 {
    state.affine.iter().map(|value| value * value).sum::<f64>()
}

/// Whether every number of the state is finite: `x · 0` is zero for finite `x` and NaN for
/// infinities and NaN, so one comparison of the sum replaces nine branches.
#[inline]
pub(super) fn is_finite(state: &ParticleState) -> bool {
    let zero = state.position[0] * 0.0
        + state.position[1] * 0.0
        + state.velocity[0] * 0.0
        + state.velocity[1] * 0.0
        + state.affine[0] * 0.0
        + state.affine[1] * 0.0
        + state.affine[2] * 0.0
        + state.affine[3] * 0.0
        + state.volume_ratio * 0.0;
    zero == 0.0
}

/// Clamps a position into `limits` (low corner, high corner); returns whether it moved.
#[inline]
pub(super) fn clamp_position(position: &mut [f64; 2], limits: [[f64; 2]; 2]) -> bool {
    let mut clamped = false;
    for axis in 0..2 {
        let value = position[axis];
        if value < limits[0][axis] || value > limits[1][axis] {
            position[axis] = value.clamp(limits[0][axis], limits[1][axis]);
            clamped = true;
        }
    }
    clamped
}
