//! The grid side of the substep: binning particles by block, and turning the blocks' tiles into
//! grid velocities.
//!
//! **Binning** is a stable counting sort by block. Particles move a small fraction of a cell per
//! substep, so the order from the last substep is usually almost right; the sort only computes
//! the permutation ([`Bins::bin`]) and the scatter applies it while it reads the particles anyway, so
//! no separate pass copies the particle state.
//!
//! **Merge and update** ([`merge_and_update`]): each grid node is the sum, in block order, of
//! the tiles that cover it (its own block's and, for the two rows and columns at a block's low
//! edges, the tiles of the blocks before it), then becomes a velocity (momentum over mass, plus
//! gravity, walls, colliders). The sum is pulled per node rather than pushed per tile, so bands
//! of block rows run in parallel and every node still adds its tiles in block order: the same
//! bytes for any thread count. Blocks that no tile reaches are skipped: no particle's stencil
//! reads them this substep, so neither the full-grid clear nor the full-grid update is needed.

use rayon::prelude::*;

use super::GridSpec;
use super::collider::{ColliderGrid, project};
use super::transfer::{BLOCK, TILE};

/// Marks a block without particles in the block-to-tile map.
pub(super) const NO_TILE: u32 = u32::MAX;

/// Blocks along each axis of a grid.
pub(super) fn blocks_along(grid: &GridSpec) -> [usize; 2] {
    [grid.nodes[0].div_ceil(BLOCK), grid.nodes[1].div_ceil(BLOCK)]
}

/// The block holding base node `base`, clamped into the block range so a corrupt position
/// cannot index outside the tables.
#[inline]
pub(super) fn block_key(base: [u32; 2], along: [usize; 2]) -> u32 {
    let bx = (base[0] as usize / BLOCK).min(along[0] - 1);
    let by = (base[1] as usize / BLOCK).min(along[1] - 1);
    index_u32(bx * along[1] + by)
}

/// Whether node `[i, j]` was summed and updated this substep: a tile covers its block (its own,
/// or one of the blocks below and to the left, whose tiles reach two nodes over).
pub(super) fn node_is_live(tile_of: &[u32], along: [usize; 2], node: [usize; 2]) -> bool {
    let (bx, by) = (node[0] / BLOCK, node[1] / BLOCK);
    let has_tile = |bx: Option<usize>, by: Option<usize>| match (bx, by) {
        (Some(bx), Some(by)) if bx < along[0] && by < along[1] => tile_of
            .get(bx * along[1] + by)
            .is_some_and(|&tile| tile != NO_TILE),
        _ => false,
    };
    has_tile(Some(bx), Some(by))
        || has_tile(bx.checked_sub(1), Some(by))
        || has_tile(Some(bx), by.checked_sub(1))
        || has_tile(bx.checked_sub(1), by.checked_sub(1))
}

/// The low corner node of a block.
pub(super) fn block_corner(block: u32, along: [usize; 2]) -> [usize; 2] {
    let block = block as usize;
    [(block / along[1]) * BLOCK, (block % along[1]) * BLOCK]
}

/// A particle, block or material index as stored: particle ids are `u32` (`add_particle` refuses
/// the 2³²-th), and grids have at most 2³⁰ nodes.
#[inline]
#[expect(
    clippy::cast_possible_truncation,
    reason = "indices are bounded by the u32 particle ids and the grid size"
)]
pub(super) fn index_u32(index: usize) -> u32 {
    index as u32
}

/// The result of binning: which blocks have particles and in what order particles go.
#[derive(Debug, Default)]
pub(super) struct Bins {
    /// Non-empty blocks in block order: (block index, first particle, end) in the binned order.
    pub(super) blocks: Vec<(u32, u32, u32)>,
    /// Per block: its index in `blocks` (and in the tiles), or [`NO_TILE`].
    pub(super) tile_of: Vec<u32>,
    /// When not `sorted`: slot `k` of the binned order takes particle `order[k]`.
    pub(super) order: Vec<u32>,
    /// Whether the particles already are in block order (then `order` is not used).
    pub(super) sorted: bool,
    /// Scratch of the counting sort: running slot per block.
    starts: Vec<u32>,
}

impl Bins {
    /// Bins particles with block keys `block_of` (each below `block_count`), stably.
    pub(super) fn bin(&mut self, block_of: &[u32], block_count: usize) {
        for &(block, _, _) in &self.blocks {
            if let Some(slot) = self.tile_of.get_mut(block as usize) {
                *slot = NO_TILE;
            }
        }
        self.tile_of.resize(block_count, NO_TILE);
        self.blocks.clear();
        self.sorted = block_of.is_sorted();
        if self.sorted {
            let mut start = 0usize;
            for index in 1..=block_of.len() {
                let (Some(&first), next) = (block_of.get(start), block_of.get(index)) else {
                    break;
                };
                if next != Some(&first) {
                    self.blocks
                        .push((first, index_u32(start), index_u32(index)));
                    start = index;
                }
            }
        } else {
            self.starts.clear();
            self.starts.resize(block_count + 1, 0);
            for &block in block_of {
                if let Some(count) = self.starts.get_mut(block as usize + 1) {
                    *count += 1;
                }
            }
            for block in 0..block_count {
                let (start, end) = (
                    self.starts[block],
                    self.starts[block] + self.starts[block + 1],
                );
                if end > start {
                    self.blocks.push((index_u32(block), start, end));
                }
                self.starts[block + 1] = end;
            }
            self.order.clear();
            self.order.resize(block_of.len(), 0);
            for (index, &block) in block_of.iter().enumerate() {
                if let Some(slot) = self.starts.get_mut(block as usize) {
                    if let Some(entry) = self.order.get_mut(*slot as usize) {
                        *entry = index_u32(index);
                    }
                    *slot += 1;
                }
            }
        }
        for (tile, &(block, _, _)) in self.blocks.iter().enumerate() {
            if let Some(slot) = self.tile_of.get_mut(block as usize) {
                *slot = index_u32(tile);
            }
        }
    }
}

/// What the grid update needs besides the nodes and tiles.
pub(super) struct GridUpdate<'a> {
    pub(super) grid: &'a GridSpec,
    /// `dt · gravity`.
    pub(super) gravity: [f64; 2],
    pub(super) colliders: &'a ColliderGrid,
    pub(super) tiles: &'a [[f64; 3]],
    pub(super) tile_of: &'a [u32],
}

/// Sums the tiles into the nodes of every block a tile reaches and turns them into velocities,
/// in parallel over bands of one block row.
pub(super) fn merge_and_update(nodes: &mut [[f64; 3]], update: &GridUpdate<'_>) {
    let columns = update.grid.nodes[1];
    nodes
        .par_chunks_mut(BLOCK * columns)
        .enumerate()
        .for_each(|(bx, band)| {
            let along = blocks_along(update.grid);
            for by in 0..along[1] {
                merge_block(band, [bx, by], along, update);
            }
        });
}

/// The tile of block `(bx, by)`, if it has one (`None` also off the low edges).
fn tile<'a>(
    update: &GridUpdate<'a>,
    along: [usize; 2],
    bx: Option<usize>,
    by: Option<usize>,
) -> Option<&'a [[f64; 3]]> {
    let (bx, by) = (bx?, by?);
    let index = *update.tile_of.get(bx * along[1] + by)? as usize;
    update
        .tiles
        .get(index * TILE * TILE..(index + 1) * TILE * TILE)
}

/// Merges and updates the nodes of one block; `band` holds the block's row of blocks.
fn merge_block(
    band: &mut [[f64; 3]],
    block: [usize; 2],
    along: [usize; 2],
    update: &GridUpdate<'_>,
) {
    let [bx, by] = block;
    // The four tiles that can cover this block's nodes, in block order.
    let covering = [
        (
            tile(update, along, bx.checked_sub(1), by.checked_sub(1)),
            [BLOCK, BLOCK],
        ),
        (tile(update, along, bx.checked_sub(1), Some(by)), [BLOCK, 0]),
        (tile(update, along, Some(bx), by.checked_sub(1)), [0, BLOCK]),
        (tile(update, along, Some(bx), Some(by)), [0, 0]),
    ];
    if covering.iter().all(|(tile, _)| tile.is_none()) {
        return;
    }
    let nodes = update.grid.nodes;
    let corner = [bx * BLOCK, by * BLOCK];
    let rows = BLOCK.min(nodes[0] - corner[0]);
    let width = BLOCK.min(nodes[1] - corner[1]);
    // Sums start from zero, as a cleared grid did.
    let mut sums = [[0.0f64; 3]; BLOCK * BLOCK];
    for (tile, offset) in covering {
        let Some(tile) = tile else { continue };
        // The part of the tile over this block: rows/columns from `offset` in the tile, which
        // is the whole block for its own tile and two rows or columns for the others.
        let tile_rows = (TILE - offset[0]).min(rows);
        let tile_width = (TILE - offset[1]).min(width);
        for a in 0..tile_rows {
            let from = (offset[0] + a) * TILE + offset[1];
            let (Some(source), Some(target)) = (
                tile.get(from..from + tile_width),
                sums.get_mut(a * BLOCK..a * BLOCK + tile_width),
            ) else {
                continue;
            };
            for (sum, value) in target.iter_mut().zip(source) {
                sum[0] += value[0];
                sum[1] += value[1];
                sum[2] += value[2];
            }
        }
    }
    let columns = nodes[1];
    for a in 0..rows {
        let start = a * columns + corner[1];
        let (Some(target), Some(source)) = (
            band.get_mut(start..start + width),
            sums.get(a * BLOCK..a * BLOCK + width),
        ) else {
            continue;
        };
        for (b, (node, sum)) in target.iter_mut().zip(source).enumerate() {
            *node = node_velocity(*sum, [corner[0] + a, corner[1] + b], update);
        }
    }
}

/// Momentum to velocity, gravity, domain walls, colliders for node `index` (`[i, j]`).
#[inline]
fn node_velocity(node: [f64; 3], index: [usize; 2], update: &GridUpdate<'_>) -> [f64; 3] {
    if node[2] <= 0.0 {
        return [0.0, 0.0, node[2]];
    }
    let nodes = update.grid.nodes;
    let walls = update.grid.walls;
    let [i, j] = index;
    let mut velocity = [
        node[0] / node[2] + update.gravity[0],
        node[1] / node[2] + update.gravity[1],
    ];
    if i < walls.low && velocity[0] < 0.0
        || i >= nodes[0].saturating_sub(walls.high) && velocity[0] > 0.0
    {
        velocity[0] = 0.0;
    }
    if j < walls.low && velocity[1] < 0.0
        || j >= nodes[1].saturating_sub(walls.high) && velocity[1] > 0.0
    {
        velocity[1] = 0.0;
    }
    if update.colliders.has_colliders()
        && let Some((normal, boundary)) = update.colliders.constraint(i * nodes[1] + j)
    {
        velocity = project(velocity, normal, boundary);
    }
    [velocity[0], velocity[1], node[2]]
}
