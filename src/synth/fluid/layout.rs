//! A fluid scene's layout, sampled as the release's `FluidSlidesSampler` samples it
//! (`FORMAT.md` §3.1): the tank, up to eight sticks placed from the top down at ±25/35/45/55°,
//! two to four containers with funnel sticks along the bottom, three or four fluids with
//! distinct densities and not all the same viscosity, and one or two later (predictive) emitters.
//!
//! Coordinates: the sampler works in the tank's local frame, origin at the tank's bottom-left
//! inner corner (`O_x`, `O_y` in world units), `x` to the right and `y` up, in units; world
//! positions add [`ORIGIN`]. Every draw comes from the caller's seeded RNG, in the release's order.

use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

use crate::perception::palette::PALETTE;
use crate::physics::fluid::{cross, segment_distance, segments_intersect};

/// Tank inner width and height, units (`container_size_range`).
pub const TANK: [f64; 2] = [5.0, 2.5];
/// Wall thickness, units.
pub const WALL_THICKNESS: f64 = 0.5;
/// Clearance between the sticks' band and the side walls, units (`stick_unpenetration_thickness_X`).
pub const SIDE_CLEARANCE: f64 = 0.2;
/// Room above the sticks' band for the emitters, units (`stick_unpenetration_thickness_YUp`).
pub const ROOM_ABOVE: f64 = 1.6;
/// Room below the sticks' band for the fall to the funnels, units
/// (`stick_unpenetration_thickness_YDown`).
pub const ROOM_BELOW: f64 = 1.5;
/// World position of the local origin (`O_x`, `O_y`).
pub const ORIGIN: [f64; 2] = [-TANK[0] / 2.0, -TANK[1] / 2.0];
/// Stick thickness and depth, units (`receptor_scale_y`, `receptor_scale_z`).
pub const STICK_SCALE: [f64; 2] = [0.15, 0.2];
/// Emitter edge width, units.
pub const EMITTER_WIDTH: f64 = 0.5;
/// Particles each emitter releases.
pub const EMITTER_CAPACITY: usize = 1500;

const MAX_STICKS: usize = 7;
const MAX_STICK_TRIES: usize = 200;
const STICK_LENGTH: (f64, f64) = (1.7, 3.0);
const STICK_MIN_DISTANCE: f64 = 0.7;
const WALL_EPSILON: f64 = 0.1;
const ROTATABLE_PROBABILITY: f64 = 0.25;
const ANGLES_DEG: [f64; 8] = [-25.0, 25.0, -35.0, 35.0, -45.0, 45.0, -55.0, 55.0];
const Y_STEP: f64 = 0.05;
const X_STEP: f64 = 0.2;
/// Palette ids of the stick and container colours (`stick_clr_range`).
const STICK_COLORS: [usize; 12] = [11, 0, 10, 1, 2, 3, 4, 5, 6, 7, 8, 9];
/// Palette ids of the fluid colours (`fluid_clr_range`; 12 is "Light Blue").
const FLUID_COLORS: [usize; 7] = [1, 2, 3, 4, 5, 7, 12];
const CONTAINER_COUNTS: [usize; 3] = [2, 3, 4];
const RECEPTOR_WIDTH: f64 = 0.6;
const RECEPTOR_HEIGHT: f64 = 0.5;
const CUP_HEIGHT: f64 = 0.7;
const REACH_IN: f64 = 0.15;

/// A stick: a 0.15-thick bar between two points of the local frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Stick {
    /// Scene name (`Red Stick`, `Red Container Left Guided Stick`).
    pub name: String,
    /// Palette id of its colour.
    pub color: usize,
    /// One end, local units.
    pub start: [f64; 2],
    /// The other end, local units.
    pub end: [f64; 2],
    /// The release's `isRotatable` flag (sampled, never used for motion: the regular prefab).
    pub rotatable: bool,
}

impl Stick {
    fn centre(&self) -> [f64; 2] {
        [
            f64::midpoint(self.start[0], self.end[0]),
            f64::midpoint(self.start[1], self.end[1]),
        ]
    }

    /// Length, units.
    pub fn length(&self) -> f64 {
        (self.end[0] - self.start[0]).hypot(self.end[1] - self.start[1])
    }

    /// The release's `angle`: `atan(dy/dx)`, π/2 for a vertical stick.
    pub fn angle(&self) -> f64 {
        if self.end[0] - self.start[0] < 0.0001 {
            std::f64::consts::FRAC_PI_2
        } else {
            ((self.end[1] - self.start[1]) / (self.end[0] - self.start[0])).atan()
        }
    }

    fn shifted(&self, dy: f64) -> Stick {
        Stick {
            start: [self.start[0], self.start[1] + dy],
            end: [self.end[0], self.end[1] + dy],
            ..self.clone()
        }
    }

    /// World end points.
    pub fn world(&self) -> ([f64; 2], [f64; 2]) {
        (to_world(self.start), to_world(self.end))
    }
}

/// A container (the release's "receptor"): a cup with two funnel sticks above it.
#[derive(Debug, Clone, PartialEq)]
pub struct Container {
    /// Scene name (`Red Container`).
    pub name: String,
    /// Palette id of its colour.
    pub color: usize,
    /// Cup centre, local units.
    pub position: [f64; 2],
    /// Cup width and height, units.
    pub scale: [f64; 2],
    /// Funnel stick on its left.
    pub left: Stick,
    /// Funnel stick on its right.
    pub right: Stick,
}

/// A fluid and its emitters.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidSpec {
    /// Scene name (`Blue Fluid`), also its emitter's object name.
    pub name: String,
    /// Palette id of its colour.
    pub color: usize,
    /// Rest density.
    pub density: f64,
    /// `true` for "Sticky" (Obi viscosity 10), `false` for "Non-Sticky" (0.02).
    pub sticky: bool,
    /// Surface tension (1 in the release).
    pub surface_tension: f64,
    /// Emitter centre, local units.
    pub emitter: [f64; 2],
    /// The later (predictive) emitter's centre, local units, when it has one.
    pub later_emitter: Option<[f64; 2]>,
}

impl FluidSpec {
    /// Obi viscosity of the fluid.
    pub fn viscosity(&self) -> f64 {
        if self.sticky { 10.0 } else { 0.02 }
    }

    /// The release's viscosity word.
    pub fn viscosity_word(&self) -> &'static str {
        if self.sticky { "Sticky" } else { "Non-Sticky" }
    }

    /// The later emitter's fluid name (`Later Emitted Blue Fluid`).
    pub fn later_name(&self) -> String {
        format!("Later Emitted {}", self.name)
    }
}

/// A sampled scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Regular sticks, lowest first (the release sorts them by height before naming).
    pub sticks: Vec<Stick>,
    /// Containers, left to right.
    pub containers: Vec<Container>,
    /// Fluids in emitter order.
    pub fluids: Vec<FluidSpec>,
}

/// A local point in world units.
pub fn to_world(local: [f64; 2]) -> [f64; 2] {
    [local[0] + ORIGIN[0], local[1] + ORIGIN[1]]
}

/// The colour's name (`Light Blue`), as scene names spell it.
pub fn color_name(color: usize) -> &'static str {
    PALETTE.get(color).map_or("Gray", |entry| entry.name)
}

/// Samples one layout, drawing from `rng` in the release's order.
pub fn sample_layout(rng: &mut ChaCha8Rng) -> Layout {
    let mut sticks = sample_sticks(rng);
    // `_Sample_Colors`: sorted by height, then every stick a distinct colour.
    sticks.sort_by(|a, b| a.centre()[1].total_cmp(&b.centre()[1]));
    let mut colors = STICK_COLORS.to_vec();
    colors.shuffle(rng);
    for (stick, &color) in sticks.iter_mut().zip(&colors) {
        stick.color = color;
        stick.name = format!("{} Stick", color_name(color));
    }
    let containers = sample_containers(rng);
    let fluids = sample_fluids(rng);
    Layout {
        sticks,
        containers,
        fluids,
    }
}

fn sample_stick_at_top(rng: &mut ChaCha8Rng, angles: &[f64]) -> Stick {
    let angle = angles[rng.random_range(0..angles.len())].to_radians();
    let length = rng.random::<f64>() * (STICK_LENGTH.1 - STICK_LENGTH.0) + STICK_LENGTH.0;
    let (dw, dh) = (length * angle.cos(), length * angle.sin());
    let span = dw.abs() + WALL_EPSILON;
    let x = rng.random::<f64>() * (TANK[0] - span) + span / 2.0;
    Stick {
        name: String::new(),
        color: 0,
        start: [x - dw / 2.0, TANK[1] - dh / 2.0],
        end: [x + dw / 2.0, TANK[1] + dh / 2.0],
        rotatable: rng.random::<f64>() < ROTATABLE_PROBABILITY,
    }
}

/// `SampleSticks`: sticks dropped from the top in steps of 0.05 until they keep 0.7 units from
/// every other, alternating between the odd and even angle lists; then one pass along `x` that
/// fills gaps with a stick of one sampled shape.
fn sample_sticks(rng: &mut ChaCha8Rng) -> Vec<Stick> {
    let odd: Vec<f64> = ANGLES_DEG.iter().skip(1).step_by(2).copied().collect();
    let even: Vec<f64> = ANGLES_DEG.iter().step_by(2).copied().collect();
    let lists = [odd, even];
    let mut which = rng.random_range(0..2_usize);
    let mut sticks: Vec<Stick> = Vec::new();
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "the tank height over the step is a small positive count"
    )]
    let steps = (TANK[1] / Y_STEP) as usize + 1;
    let drop = |sticks: &[Stick], stick: Stick| -> Option<Stick> {
        let mut candidate = stick;
        for _ in 0..steps {
            if valid_with_others(sticks, &candidate) {
                return Some(candidate);
            }
            candidate = candidate.shifted(-Y_STEP);
        }
        None
    };
    let mut attempts = 0;
    while sticks.len() < MAX_STICKS && attempts <= MAX_STICK_TRIES {
        attempts += 1;
        let stick = sample_stick_at_top(rng, &lists[which]);
        if let Some(placed) = drop(&sticks, stick) {
            attempts = 0;
            which = 1 - which;
            sticks.push(placed);
        }
    }
    let shape = sample_stick_at_top(rng, &ANGLES_DEG);
    let length = shape.length();
    let (dx, dy) = (shape.start[0] - shape.end[0], shape.start[1] - shape.end[1]);
    #[expect(
        clippy::cast_possible_truncation,
        reason = "a span over the step is a small count"
    )]
    let x_steps = ((TANK[0] - length) / X_STEP).max(-1.0) as i64 + 1;
    for i in 0..x_steps.max(0) {
        if sticks.len() > MAX_STICKS {
            break;
        }
        #[expect(clippy::cast_precision_loss, reason = "a small step index")]
        let x = i as f64 * X_STEP + length / 2.0;
        let y = shape.centre()[1];
        let sign = if rng.random::<f64>() < 0.5 { -1.0 } else { 1.0 };
        let stick = Stick {
            name: String::new(),
            color: 0,
            start: [x - dx / 2.0, y + sign * dy / 2.0],
            end: [x + dx / 2.0, y - sign * dy / 2.0],
            rotatable: false,
        };
        if let Some(placed) = drop(&sticks, stick) {
            sticks.push(placed);
        }
    }
    sticks
}

/// `CheckValidityOfNewStickWithOthers`: at least 0.7 units from every other stick, and no
/// rotatable stick's sweep (two triangles round its centre) crossing another.
fn valid_with_others(sticks: &[Stick], new: &Stick) -> bool {
    sticks.iter().all(|stick| {
        if segment_distance(stick.start, stick.end, new.start, new.end) < STICK_MIN_DISTANCE {
            return false;
        }
        match (new.rotatable, stick.rotatable) {
            (true, true) => !fans_intersect(stick, new),
            (true, false) => !fan_crosses(new, stick),
            (false, true) => !fan_crosses(stick, new),
            (false, false) => true,
        }
    })
}

/// `rotatorTriangles`: the two triangles a rotatable stick would sweep.
fn fan(stick: &Stick) -> [[[f64; 2]; 3]; 2] {
    let [x1, y1] = stick.centre();
    let r = stick.length() / 2.0;
    let slope = stick.angle().tan();
    let (y2, y3) = (slope * r + y1, -slope * r + y1);
    let centre = [x1, y1];
    [
        [centre, [x1 + r, y2], [x1 + r, y3]],
        [centre, [x1 - r, y2], [x1 - r, y3]],
    ]
}

fn triangle_crossed(triangle: &[[f64; 2]; 3], p: [f64; 2], q: [f64; 2]) -> bool {
    (0..3).any(|i| segments_intersect(triangle[i], triangle[(i + 1) % 3], p, q))
}

fn inside_triangle(p: [f64; 2], t: &[[f64; 2]; 3]) -> bool {
    let same = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| cross(a, b, p) * cross(a, b, c) >= 0.0;
    same(t[0], t[1], t[2]) && same(t[1], t[2], t[0]) && same(t[2], t[0], t[1])
}

fn triangles_intersect(a: &[[f64; 2]; 3], b: &[[f64; 2]; 3]) -> bool {
    (0..3).any(|i| inside_triangle(a[i], b) || inside_triangle(b[i], a))
        || (0..3)
            .any(|i| (0..3).any(|j| segments_intersect(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])))
}

fn fan_crosses(rotator: &Stick, segment: &Stick) -> bool {
    fan(rotator)
        .iter()
        .any(|t| triangle_crossed(t, segment.start, segment.end))
}

fn fans_intersect(first: &Stick, second: &Stick) -> bool {
    let (a, b) = (fan(first), fan(second));
    a.iter()
        .any(|s| b.iter().any(|t| triangles_intersect(s, t)))
}

/// `_Sample_Receptors`: 2–4 cups evenly spaced across the tank's floor, each under two funnel
/// sticks that rise from the cup's rim to the band's bottom at the cup's share's edges.
fn sample_containers(rng: &mut ChaCha8Rng) -> Vec<Container> {
    let width = TANK[0] + 2.0 * SIDE_CLEARANCE;
    let height = TANK[1];
    let count = CONTAINER_COUNTS[rng.random_range(0..CONTAINER_COUNTS.len())];
    let mut colors = STICK_COLORS.to_vec();
    colors.shuffle(rng);
    #[expect(clippy::cast_precision_loss, reason = "2 to 4 containers")]
    let unit = width / count as f64;
    let cup_offset = -RECEPTOR_HEIGHT * height;
    let cup_width = RECEPTOR_WIDTH * unit;
    let cup_height = CUP_HEIGHT * RECEPTOR_HEIGHT * height;
    (0..count)
        .map(|index| {
            #[expect(clippy::cast_precision_loss, reason = "2 to 4 containers")]
            let i = index as f64;
            let cup_y = cup_height / 2.0 + cup_offset;
            let cup_x = unit / 2.0 + i * unit;
            let color = colors[index];
            let name = format!("{} Container", color_name(color));
            let reach_left = cup_x - cup_width * (0.5 - REACH_IN);
            let reach_right = cup_x + cup_width * (0.5 - REACH_IN);
            let (upper_left, upper_right, upper_y) = (i * unit, (i + 1.0) * unit, 0.0);
            let rim = [cup_x - cup_width / 2.0, cup_y + cup_height / 2.0];
            let slope = (rim[1] - upper_y) / (rim[0] - upper_left);
            let reach_y = upper_y + slope * (reach_left - upper_left);
            let shift = |p: [f64; 2]| [p[0] - SIDE_CLEARANCE, p[1] - ROOM_BELOW];
            let funnel = |side: &str, upper: f64, reach: f64| Stick {
                name: format!("{name} {side} Guided Stick"),
                color,
                start: shift([upper, upper_y]),
                end: shift([reach, reach_y]),
                rotatable: false,
            };
            Container {
                left: funnel("Left", upper_left, reach_left),
                right: funnel("Right", upper_right, reach_right),
                position: shift([cup_x, cup_y]),
                scale: [cup_width, cup_height],
                color,
                name,
            }
        })
        .collect()
}

/// `_Sample_Fluids`: 3 or 4 fluids with shuffled densities from the pool, distinct colours, one
/// or two with a later emitter; emitters at least an edge's width apart along the ceiling.
fn sample_fluids(rng: &mut ChaCha8Rng) -> Vec<FluidSpec> {
    let count = if rng.random::<bool>() { 3 } else { 4 };
    let later_count = if rng.random::<bool>() { 1 } else { 2 };
    let mut densities: Vec<f64> = if count == 3 {
        vec![1600.0, 3000.0, 4400.0]
    } else {
        vec![1200.0, 2600.0, 4000.0, 5400.0]
    };
    densities.shuffle(rng);
    let mut indices: Vec<usize> = (0..count).collect();
    indices.shuffle(rng);
    let with_later: Vec<usize> = indices[..later_count].to_vec();
    let mut colors = FLUID_COLORS.to_vec();
    colors.shuffle(rng);
    let emitters = count + later_count;
    let positions = loop {
        let mut placed: Vec<f64> = Vec::new();
        for _ in 0..emitters {
            let spot = (0..100).find_map(|_| {
                let x = rng.random::<f64>() * (TANK[0] - EMITTER_WIDTH);
                placed
                    .iter()
                    .all(|p| (p - x).abs() >= EMITTER_WIDTH)
                    .then_some(x)
            });
            match spot {
                Some(x) => placed.push(x),
                None => break,
            }
        }
        if placed.len() == emitters {
            break placed;
        }
    };
    let emitter_y = TANK[1] + WALL_THICKNESS / 2.0 + ROOM_ABOVE - WALL_THICKNESS / 2.0;
    let mut next = positions
        .into_iter()
        .map(|x| [x + EMITTER_WIDTH / 2.0, emitter_y]);
    let mut fluids: Vec<FluidSpec> = (0..count)
        .map(|i| {
            let color = colors[i];
            FluidSpec {
                name: format!("{} Fluid", color_name(color)),
                color,
                density: densities[i],
                sticky: rng.random::<bool>(),
                surface_tension: 1.0,
                emitter: next.next().unwrap_or([0.0, emitter_y]),
                later_emitter: if with_later.contains(&i) {
                    next.next()
                } else {
                    None
                },
            }
        })
        .collect();
    // Viscosities never all the same: one fluid, chosen at random, takes the other.
    if fluids.iter().all(|f| f.sticky == fluids[0].sticky) {
        let flip = rng.random_range(0..count);
        fluids[flip].sticky = !fluids[flip].sticky;
    }
    fluids
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;

    #[test]
    fn layouts_follow_the_release_rules() {
        for seed in 0..40 {
            let layout = sample_layout(&mut seeded_rng(seed));
            let sticks = &layout.sticks;
            assert!(
                (1..=8).contains(&sticks.len()),
                "seed {seed}: {} sticks",
                sticks.len()
            );
            for (i, a) in sticks.iter().enumerate() {
                // Slope angle from the geometry: the release's `angle` is π/2 for a stick whose
                // start lies right of its end (the fill pass's mirrored sticks), a quirk it writes.
                let slope = (a.end[1] - a.start[1]) / (a.end[0] - a.start[0]);
                let degrees = slope.atan().to_degrees().abs().round();
                assert!(
                    [25.0, 35.0, 45.0, 55.0].contains(&degrees),
                    "seed {seed}: {degrees}"
                );
                assert!((1.7..=3.0 + 1e-9).contains(&a.length()));
                assert!(
                    a.start[1].max(a.end[1]) <= TANK[1] + 1.5,
                    "seed {seed}: above the band"
                );
                for b in &sticks[i + 1..] {
                    assert!(segment_distance(a.start, a.end, b.start, b.end) >= 0.7 - 1e-9);
                    assert_ne!(a.color, b.color, "seed {seed}: stick colours are distinct");
                }
            }
            assert!((2..=4).contains(&layout.containers.len()));
            let fluids = &layout.fluids;
            assert!((3..=4).contains(&fluids.len()));
            assert!(fluids.iter().any(|f| f.sticky) && fluids.iter().any(|f| !f.sticky));
            let later = fluids.iter().filter(|f| f.later_emitter.is_some()).count();
            assert!((1..=2).contains(&later));
            let mut densities: Vec<f64> = fluids.iter().map(|f| f.density).collect();
            densities.sort_by(f64::total_cmp);
            let pool: &[f64] = if fluids.len() == 3 {
                &[1600.0, 3000.0, 4400.0]
            } else {
                &[1200.0, 2600.0, 4000.0, 5400.0]
            };
            assert_eq!(densities, pool);
            let mut xs: Vec<f64> = fluids
                .iter()
                .flat_map(|f| std::iter::once(f.emitter).chain(f.later_emitter))
                .map(|p| p[0])
                .collect();
            xs.sort_by(f64::total_cmp);
            assert!(xs.windows(2).all(|w| w[1] - w[0] >= EMITTER_WIDTH - 1e-9));
        }
    }

    #[test]
    fn containers_sit_on_the_floor_under_funnels_that_meet_between_them() {
        let layout = sample_layout(&mut seeded_rng(3));
        let containers = &layout.containers;
        for pair in containers.windows(2) {
            let (right, left) = (pair[0].right.start, pair[1].left.start);
            assert!(
                (right[0] - left[0]).abs() < 1e-12 && (right[1] - left[1]).abs() < 1e-12,
                "funnels share their top"
            );
        }
        for c in containers {
            let bottom = to_world([0.0, c.position[1] - c.scale[1] / 2.0])[1];
            // Floor top: the floor's centre is a wall thickness and the room below the cups.
            assert!((bottom - (-4.0)).abs() < 1e-9, "cup bottom at {bottom}");
            let (top, reach) = c.left.world();
            assert!((top[1] - (-2.75)).abs() < 1e-9 && reach[1] < top[1]);
        }
        let first = to_world(containers[0].left.start)[0];
        let last = to_world(containers[containers.len() - 1].right.start)[0];
        assert!((first + 2.7).abs() < 1e-9 && (last - 2.7).abs() < 1e-9);
    }
}
