//! The colour pools objects and ropes take their colours from, and the random load shape.

use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

use super::super::super::palette::{LIGHT_COLORS, palette_color};
use super::LoadShape;
// The base colour lists of objects and ropes are the release's, shared with perception, which
// reads a colour among those its class can have.
use crate::perception::rope::{OBJECT_COLORS, ROPE_COLORS};

/// A colour pool: a shuffled base list followed by the light colours; past its end it keeps
/// returning its first colour (the release's `take`).
pub(super) struct Pool {
    colors: Vec<u8>,
    next: usize,
}

impl Pool {
    fn new(base: &[u8], rng: &mut ChaCha8Rng) -> Pool {
        let mut colors = base.to_vec();
        colors.shuffle(rng);
        colors.extend_from_slice(&LIGHT_COLORS);
        Pool { colors, next: 0 }
    }

    pub(super) fn take(&mut self) -> u8 {
        let color = self
            .colors
            .get(self.next)
            .copied()
            .unwrap_or(self.colors[0]);
        self.next += 1;
        color
    }
}

/// The release's colour pools, one per kind of object and one for ropes.
pub(super) struct Pools {
    pub(super) movable_solid: Pool,
    pub(super) movable_hollow: Pool,
    cube: Pool,
    sphere: Pool,
    static_solid: Pool,
    static_hollow: Pool,
    pub(super) fixed_point: Pool,
    pub(super) rope: Pool,
}

impl Pools {
    pub(super) fn new(rng: &mut ChaCha8Rng) -> Pools {
        Pools {
            movable_solid: Pool::new(&OBJECT_COLORS, rng),
            movable_hollow: Pool::new(&OBJECT_COLORS, rng),
            cube: Pool::new(&OBJECT_COLORS, rng),
            sphere: Pool::new(&OBJECT_COLORS, rng),
            static_solid: Pool::new(&OBJECT_COLORS, rng),
            static_hollow: Pool::new(&OBJECT_COLORS, rng),
            fixed_point: Pool::new(&OBJECT_COLORS, rng),
            rope: Pool::new(&ROPE_COLORS, rng),
        }
    }

    pub(super) fn load(&mut self, shape: LoadShape) -> u8 {
        match shape {
            LoadShape::Cube => self.cube.take(),
            LoadShape::Sphere => self.sphere.take(),
        }
    }

    pub(super) fn static_pulley(&mut self, solid: bool) -> u8 {
        if solid {
            self.static_solid.take()
        } else {
            self.static_hollow.take()
        }
    }
}

pub(super) fn color_name(id: u8) -> &'static str {
    palette_color(id).map_or("Gray", |c| c.name)
}

pub(super) fn random_shape(rng: &mut ChaCha8Rng) -> LoadShape {
    if rng.random::<f64>() < 0.5 {
        LoadShape::Cube
    } else {
        LoadShape::Sphere
    }
}
