//! A ball scene's layout, sampled as the release's `SoftBodySampler` samples it (`FORMAT.md`
//! §5.1, `docs/data/ball.md`): a stadium of half-width W with a ramp on each side, a floor in
//! three pieces leaving two pits, a slanted and a vertical floating wall, and three balls of
//! the three materials dropped above the slanted wall and the two ramps.
//!
//! World coordinates, units, `y` up, the stadium centred on `x = 0`. Every draw comes from the
//! caller's seeded RNG. Thicknesses the release's prefabs set and its configs do not record
//! are this generator's choices, named below.

use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

use crate::dataset::ball::ElasticityType;
use crate::dataset::ball::names::{FLOOR_PIECES, RAMPS, ball_name, floating_wall_name};
use crate::dataset::palette::PALETTE_NAMES;

/// The floor's level (its centre line), units.
pub const FLOOR_LEVEL: f64 = -0.5;
/// Floor piece thickness, units (not recorded by the release: its top is then 0.1 above the
/// floor level, so a resting ball's centre is 0.6 above the drop height).
pub const FLOOR_THICKNESS: f64 = 0.2;
/// Ramp thickness, units (not recorded).
pub const RAMP_THICKNESS: f64 = 0.2;
/// Floating wall thickness, units.
pub const WALL_THICKNESS: f64 = 0.4;
/// The floating walls' top and bottom ends, units.
pub const WALL_ENDS_Y: [f64; 2] = [4.04, 1.2];
/// A pit's width, units.
pub const PIT_WIDTH: f64 = 1.2;
/// The ramps' top height, units, and their foot's.
pub const RAMP_ENDS_Y: [f64; 2] = [-0.07, 4.04];
/// Depth (z extent) of every slab as drawn, units.
pub const SLAB_DEPTH: f64 = 1.0;
/// A ball's radius, units (the prefab's unit sphere: not recorded).
pub const BALL_RADIUS: f64 = 0.5;
/// Palette ids of the ramp, wall and ball colours (White, Red, Black, Orange, Yellow, Green,
/// Cyan, Blue, Purple, Pink, Brown).
pub const COLORS: [usize; 11] = [11, 0, 10, 1, 2, 3, 4, 5, 6, 7, 8];
/// Stadium half-width range, units.
const HALF_WIDTH: (f64, f64) = (3.5, 5.5);
/// Ramp width range (its x extent), units.
const RAMP_WIDTH: (f64, f64) = (2.67, 3.3);
/// Pit centre range is `[1, W − 1.8]` from the centre, units.
const PIT_FROM_CENTRE: f64 = 1.0;
const PIT_FROM_EDGE: f64 = 1.8;
/// Floating walls keep this far inside the stadium's edges, units.
const WALL_MARGIN: f64 = 0.4;
/// The slanted wall's ends differ in x by this much, units.
const SLANT: (f64, f64) = (2.4, 3.7);
/// The vertical wall keeps this far from both ends of the slanted one, in x, units.
const WALL_CLEARANCE: f64 = 1.6;
/// Ball release height range, units.
const RELEASE_HEIGHT: (f64, f64) = (5.11, 6.9);
/// Tries at a layout whose vertical wall fits.
const MAX_TRIES: usize = 1000;

/// A slab: the rectangle round a centre line, as the release's "stick" records describe it.
#[derive(Debug, Clone, PartialEq)]
pub struct SlabLayout {
    /// Scene name.
    pub name: String,
    /// Palette id of its colour.
    pub color: usize,
    /// One end of the centre line, units.
    pub start: [f64; 2],
    /// The other end, units.
    pub end: [f64; 2],
    /// Thickness, units.
    pub thickness: f64,
}

impl SlabLayout {
    /// Length, units.
    pub fn length(&self) -> f64 {
        (self.end[0] - self.start[0]).hypot(self.end[1] - self.start[1])
    }

    /// Angle of the centre line to the x axis, radians.
    pub fn angle(&self) -> f64 {
        (self.end[1] - self.start[1]).atan2(self.end[0] - self.start[0])
    }
}

/// A ball to drop.
#[derive(Debug, Clone, PartialEq)]
pub struct BallLayoutEntry {
    /// `<C> Ball`.
    pub name: String,
    /// Palette id.
    pub color: usize,
    /// Its material.
    pub elasticity: ElasticityType,
    /// Where it is released, units.
    pub release: [f64; 3],
}

/// A sampled ball scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Stadium half-width W, units.
    pub half_width: f64,
    /// `Right Ramp`, `Left Ramp`.
    pub ramps: Vec<SlabLayout>,
    /// Floor pieces, left to right.
    pub floor_pieces: Vec<SlabLayout>,
    /// The slanted floating wall, then the vertical one.
    pub floating_walls: Vec<SlabLayout>,
    /// The balls: above the slanted wall, the right ramp, the left ramp.
    pub balls: Vec<BallLayoutEntry>,
    /// The pits' centres, `[right, left]`, units.
    pub pits: [f64; 2],
}

impl Layout {
    /// Every slab: ramps, floor pieces, floating walls.
    pub fn slabs(&self) -> impl Iterator<Item = &SlabLayout> {
        self.ramps
            .iter()
            .chain(&self.floor_pieces)
            .chain(&self.floating_walls)
    }
}

/// The palette name of an id of [`COLORS`].
pub fn color_name(id: usize) -> &'static str {
    PALETTE_NAMES.get(id).copied().unwrap_or("Gray")
}

/// Samples a layout. `None` only if no vertical wall fit in 1,000 draws of the stadium
/// and the slanted wall (it always fits for half-widths the release draws).
pub fn sample_layout(rng: &mut ChaCha8Rng) -> Option<Layout> {
    for _ in 0..MAX_TRIES {
        let half_width = rng.random_range(HALF_WIDTH.0..HALF_WIDTH.1);
        let ramp_width = rng.random_range(RAMP_WIDTH.0..RAMP_WIDTH.1);
        let pits = [
            rng.random_range(PIT_FROM_CENTRE..half_width - PIT_FROM_EDGE),
            -rng.random_range(PIT_FROM_CENTRE..half_width - PIT_FROM_EDGE),
        ];
        let low = -half_width + WALL_MARGIN;
        let high = half_width - WALL_MARGIN;
        let slant = rng.random_range(SLANT.0..SLANT.1);
        let slant_left = rng.random_bool(0.5);
        let first_x = rng.random_range(low..high - slant);
        let (top_x, bottom_x) = if slant_left {
            (first_x + slant, first_x)
        } else {
            (first_x, first_x + slant)
        };
        let span = (first_x - WALL_CLEARANCE, first_x + slant + WALL_CLEARANCE);
        let room: Vec<(f64, f64)> = [(low, span.0), (span.1, high)]
            .into_iter()
            .filter(|(a, b)| b > a)
            .collect();
        let total: f64 = room.iter().map(|(a, b)| b - a).sum();
        if total <= 0.0 {
            continue;
        }
        let mut pick = rng.random_range(0.0..total);
        let mut vertical_x = room[0].0;
        for (a, b) in &room {
            if pick < b - a {
                vertical_x = a + pick;
                break;
            }
            pick -= b - a;
        }
        let mut colors = COLORS.to_vec();
        colors.shuffle(rng);
        let mut ball_colors = COLORS.to_vec();
        ball_colors.shuffle(rng);
        let mut kinds = ElasticityType::ALL.to_vec();
        kinds.shuffle(rng);
        let ramp = |name: &str, color, side: f64| SlabLayout {
            name: name.to_string(),
            color,
            start: [side * half_width, RAMP_ENDS_Y[0]],
            end: [side * (half_width + ramp_width), RAMP_ENDS_Y[1]],
            thickness: RAMP_THICKNESS,
        };
        let ramps = vec![
            ramp(RAMPS[0], colors[0], 1.0),
            ramp(RAMPS[1], colors[1], -1.0),
        ];
        let outer = half_width + ramp_width;
        let half_pit = PIT_WIDTH / 2.0;
        let floor_ends = [
            (-outer, pits[1] - half_pit),
            (pits[1] + half_pit, pits[0] - half_pit),
            (pits[0] + half_pit, outer),
        ];
        let floor_pieces = FLOOR_PIECES
            .iter()
            .zip(floor_ends)
            .map(|(name, (a, b))| SlabLayout {
                name: (*name).to_string(),
                color: 9,
                start: [a, FLOOR_LEVEL],
                end: [b, FLOOR_LEVEL],
                thickness: FLOOR_THICKNESS,
            })
            .collect();
        let wall = |color: usize, top: f64, bottom: f64| SlabLayout {
            name: floating_wall_name(color_name(color)),
            color,
            start: [top, WALL_ENDS_Y[0]],
            end: [bottom, WALL_ENDS_Y[1]],
            thickness: WALL_THICKNESS,
        };
        let floating_walls = vec![
            wall(colors[2], top_x, bottom_x),
            wall(colors[3], vertical_x, vertical_x),
        ];
        let drop_x = [
            f64::midpoint(top_x, bottom_x),
            half_width + ramp_width / 2.0,
            -(half_width + ramp_width / 2.0),
        ];
        let balls = drop_x
            .iter()
            .zip(&ball_colors)
            .zip(&kinds)
            .map(|((x, color), kind)| BallLayoutEntry {
                name: ball_name(color_name(*color)),
                color: *color,
                elasticity: *kind,
                release: [
                    *x,
                    rng.random_range(RELEASE_HEIGHT.0..RELEASE_HEIGHT.1),
                    0.0,
                ],
            })
            .collect();
        return Some(Layout {
            half_width,
            ramps,
            floor_pieces,
            floating_walls,
            balls,
            pits,
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;

    #[test]
    fn layouts_keep_the_releases_rules() {
        for seed in 0..300 {
            let layout = sample_layout(&mut seeded_rng(seed)).unwrap();
            let w = layout.half_width;
            assert!((3.5..5.5).contains(&w));
            // Pits inside [1, W − 1.8] from the centre, one on each side.
            assert!(layout.pits[0] >= 1.0 && layout.pits[0] <= w - 1.8);
            assert!(layout.pits[1] <= -1.0 && layout.pits[1] >= -(w - 1.8));
            // Floor pieces leave exactly the two pits, 1.2 wide.
            let pieces = &layout.floor_pieces;
            assert!((pieces[1].start[0] - pieces[0].end[0] - PIT_WIDTH).abs() < 1e-12);
            assert!((pieces[2].start[0] - pieces[1].end[0] - PIT_WIDTH).abs() < 1e-12);
            // The slanted wall slants 2.4–3.7; the vertical one is vertical, clear of it by 1.6.
            let [slanted, vertical] = [&layout.floating_walls[0], &layout.floating_walls[1]];
            let slant = (slanted.start[0] - slanted.end[0]).abs();
            assert!((2.4..3.7).contains(&slant));
            assert!(vertical.start[0].to_bits() == vertical.end[0].to_bits());
            for end in [slanted.start[0], slanted.end[0]] {
                assert!((vertical.start[0] - end).abs() >= 1.6 - 1e-12);
            }
            let (lo, hi) = (
                slanted.start[0].min(slanted.end[0]),
                slanted.start[0].max(slanted.end[0]),
            );
            assert!(vertical.start[0] < lo || vertical.start[0] > hi);
            for wall in &layout.floating_walls {
                for x in [wall.start[0], wall.end[0]] {
                    assert!(x >= -w + 0.4 - 1e-12 && x <= w - 0.4 + 1e-12);
                }
            }
            // Four distinct ramp and wall colours; three distinct ball colours and materials.
            let mut slab_colors: Vec<usize> = layout
                .ramps
                .iter()
                .chain(&layout.floating_walls)
                .map(|s| s.color)
                .collect();
            slab_colors.sort_unstable();
            slab_colors.dedup();
            assert_eq!(slab_colors.len(), 4);
            let mut balls: Vec<(usize, &str)> = layout
                .balls
                .iter()
                .map(|b| (b.color, b.elasticity.as_str()))
                .collect();
            assert_eq!(balls.len(), 3);
            balls.sort_unstable();
            balls.dedup_by_key(|b| b.0);
            assert_eq!(balls.len(), 3);
            let mut kinds: Vec<&str> = layout.balls.iter().map(|b| b.elasticity.as_str()).collect();
            kinds.sort_unstable();
            assert_eq!(kinds, ["Elastic", "Plastic", "Rigid"]);
            for ball in &layout.balls {
                assert!((5.11..6.9).contains(&ball.release[1]));
            }
        }
    }
}
