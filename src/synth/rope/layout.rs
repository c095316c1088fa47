//! Random rope–pulley layouts with the release's randomisation: a port of the generator's
//! `SampleScheme` (a serpentine walk over a grid of 1–2 layers placing static pulleys, movable
//! pulleys and rope ends), `SequenceScheme` (grid slots to world positions, rope ends to loads
//! and fixed points, colour pools), the limit of two dynamic nodes per cable, names, related
//! groups and the random re-arrangement of groups (FORMAT.md §2, and the generator's
//! `PulleyGroupManager`; the probabilities and constants below are its configuration).
//!
//! Input: an RNG. Output: a [`Layout`]: elements with positions (world units), ropes as element
//! paths, related groups in the release's list forms, the load masses, and the metadata the
//! release writes. Mechanisms the simulator does not model (ropes merged end to end, closed
//! loops) and layouts the release itself loses (duplicate names, empty groups) are rejected with
//! a reason, and the caller samples again.

use indexmap::IndexMap;
use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use super::super::palette::{LIGHT_COLORS, palette_color};
use crate::dataset::rope_world as world;

const BASE_X: f64 = -20.0;
const BASE_Y: f64 = 20.0;
const X_STEP: f64 = 3.7;
const Y_STEP: f64 = 8.0;
const LAYER_STEP: f64 = 10.0;
const RADIUS_SCALE: f64 = 0.8;
const CEIL_FLOOR_SCALE: f64 = 1.0;
const OBJ_POS_SCALE: f64 = 0.7;
const UP_START_P: f64 = 0.25;
const LOW_START_P: f64 = 0.25;
const STATIC_FLAT_P: f64 = 0.2;
const LOW_STATIC_P: f64 = 0.1;
const UP_WITH_UPPER_DYN_STATIC_P: f64 = 0.05;
const UP_WITH_UPPER_DYN_END_P: f64 = 0.45;
const LOW_END_STATIC_P: f64 = 0.1;
const BIG_PULLEY_P: f64 = 0.5;
const MAX_DYNAMIC_NODES_PER_CABLE: usize = 2;
const MIN_DISTANCE_BETWEEN_GROUPS: f64 = 4.0;
const RANDOM_LAYOUT_P: f64 = 0.5;
const REARRANGED_GROUP_GAP: f64 = 7.0;
/// The factual masses a load draws from, kg (before its multiplier).
pub const LOAD_MASSES_KG: [f64; 3] = world::LOAD_MASSES_KG;

/// Slot states and element types (`metaSampling[].type`).
pub mod kind {
    /// A movable pulley waiting for a connection; carries a load when none comes.
    pub const DYNAMIC_WAIT: i32 = -1;
    /// A movable pulley carrying a load.
    pub const DYNAMIC_WITH_LOAD: i32 = 0;
    /// A movable pulley joined to another by a pulley–pulley cable.
    pub const DYNAMIC_WITH_DYN: i32 = 1;
    /// A movable pulley that another rope's end is tied to.
    pub const DYNAMIC_WITH_END: i32 = 2;
    /// A static pulley.
    pub const STATICS: i32 = 3;
    /// A fixed point on the ceiling.
    pub const END_STATIC_CEIL: i32 = 4;
    /// A fixed point on the floor.
    pub const END_STATIC_FLOO: i32 = 5;
    /// A rope end waiting for a connection; a load when none comes.
    pub const END_DYNAMIC_WAIT: i32 = 6;
    /// A load at a rope end.
    pub const END_DYNAMIC_LOAD: i32 = 7;
    /// A rope end tied to a pulley's axle.
    pub const END_DYNAMIC_PULY: i32 = 8;
    /// Two rope ends merged.
    pub const END_DYNAMIC_END: i32 = 9;
}

use kind::{
    DYNAMIC_WAIT, DYNAMIC_WITH_DYN, DYNAMIC_WITH_END, DYNAMIC_WITH_LOAD, END_DYNAMIC_END,
    END_DYNAMIC_LOAD, END_DYNAMIC_PULY, END_DYNAMIC_WAIT, END_STATIC_CEIL, END_STATIC_FLOO,
    STATICS,
};

const UPPER: i32 = 0;
const LOWER: i32 = 1;
const UPPER_FLAT: i32 = 2;
const LOWER_FLAT: i32 = 3;
const UPPER_DYN: i32 = 4;
const LOWER_DYN: i32 = 5;

fn is_upper(position: i32) -> bool {
    matches!(position, UPPER | UPPER_FLAT | UPPER_DYN)
}

/// A load's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoadShape {
    /// A cube, side 2.
    Cube,
    /// A sphere, diameter 2.
    Sphere,
}

impl LoadShape {
    fn word(self) -> &'static str {
        match self {
            LoadShape::Cube => "Cube",
            LoadShape::Sphere => "Sphere",
        }
    }
}

/// A grid slot of the walk.
#[derive(Debug, Clone)]
struct Slot {
    state: i32,
    position: i32,
    big: bool,
    x: i32,
    depth: i32,
    division: Option<usize>,
}

/// A rope end of the walk.
#[derive(Debug, Clone)]
struct Division {
    kind: i32,
    x: i32,
    depth: i32,
    target: Option<(i32, i32)>,
}

/// A pulley–pulley cable between grid slots `(x, depth)`.
#[derive(Debug, Clone, Copy)]
struct Connect {
    upper: (i32, i32),
    lower: (i32, i32),
}

/// What an element of a rope path is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// A static pulley.
    StaticPulley,
    /// A movable pulley.
    MovablePulley,
    /// A fixed point; `true` on the ceiling.
    FixedPoint(bool),
    /// A load at a rope end.
    Load,
    /// A rope end tied to the axle of the pulley named in [`Element::target`].
    TiedToPulley,
}

/// One element of a rope path (a pulley inside, an end at either side).
#[derive(Debug, Clone)]
pub struct Element {
    /// What it is.
    pub kind: ElementKind,
    /// The release's `type` code.
    pub code: i32,
    /// Scene name (empty for a tied end).
    pub name: String,
    /// Layout position (world units), after re-arrangement.
    pub position: [f64; 2],
    /// Grid slot `(layer, column)` of pulleys.
    pub grid: Option<(i32, i32)>,
    /// `(column, layer)` index into the walk's slot lists, for pulleys.
    pub in_states: Option<(usize, usize)>,
    /// Solid ("little", `scale` 0) or hollow ("big", `scale` 1) pulley.
    pub solid: bool,
    /// The release's `position` code (0 upper, 1 lower, 2/3 flat, 4/5 dynamic rows).
    pub row: i32,
    /// Colour id.
    pub color: u8,
    /// A load's shape (an end load, or the load hanging under a movable pulley).
    pub load_shape: Option<LoadShape>,
    /// The colour of the load hanging under a movable pulley.
    pub load_color: Option<u8>,
    /// The hanging load's name and its connection rope's name.
    pub hanging: Option<(String, String)>,
    /// For a tied end: the target pulley's grid slot `(column, layer)`.
    pub target: Option<(i32, i32)>,
}

impl Element {
    /// Whether the element is a pulley.
    pub fn is_pulley(&self) -> bool {
        matches!(
            self.kind,
            ElementKind::StaticPulley | ElementKind::MovablePulley
        )
    }
}

/// A main cable: its name and its path (ends and pulleys in order).
#[derive(Debug, Clone)]
pub struct LayoutRope {
    /// Scene name (`Purple Rope`).
    pub name: String,
    /// Colour id.
    pub color: u8,
    /// Ends and pulleys, in order.
    pub path: Vec<Element>,
    /// Indices of `path` that stay dynamic (`dynamicObjectIndex`).
    pub dynamic_indices: Vec<usize>,
}

/// A pulley–pulley cable between the axles of two named pulleys.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cable {
    /// Scene name.
    pub name: String,
    /// The upper pulley (layer 0).
    pub upper: String,
    /// The lower pulley.
    pub lower: String,
}

/// A sampled scene layout.
#[derive(Debug, Clone)]
pub struct Layout {
    /// Main cables.
    pub ropes: Vec<LayoutRope>,
    /// Pulley–pulley cables.
    pub cables: Vec<Cable>,
    /// `relatedGroups`.
    pub related_groups: Vec<Vec<String>>,
    /// `relatedGroupsInRope`.
    pub related_groups_in_rope: Vec<IndexMap<String, Vec<String>>>,
    /// Loads and their multipliers (1, or 1.975 under a movable pulley), in `outputMass` order.
    pub loads: Vec<(String, f64)>,
    /// Factual masses of the loads (multiplier applied), kg, in `loads` order.
    pub masses_kg: Vec<f64>,
    /// `name2position`.
    pub positions: IndexMap<String, [f64; 2]>,
    /// `name2idsInPose`.
    pub ids_in_pose: IndexMap<String, [usize; 2]>,
    /// `metaSamplingData` as the release writes it.
    pub meta: Value,
}

/// A colour pool: a shuffled base list followed by the light colours; past its end it keeps
/// returning its first colour (the release's `take`).
struct Pool {
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

    fn take(&mut self) -> u8 {
        let color = self
            .colors
            .get(self.next)
            .copied()
            .unwrap_or(self.colors[0]);
        self.next += 1;
        color
    }
}

/// The base colour list of objects (every colour but black).
const OBJECT_COLORS: [u8; 11] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11];
/// The base colour list of ropes.
const ROPE_COLORS: [u8; 9] = [0, 2, 3, 4, 5, 6, 7, 10, 11];

struct Pools {
    movable_solid: Pool,
    movable_hollow: Pool,
    cube: Pool,
    sphere: Pool,
    static_solid: Pool,
    static_hollow: Pool,
    fixed_point: Pool,
    rope: Pool,
}

impl Pools {
    fn new(rng: &mut ChaCha8Rng) -> Pools {
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

    fn load(&mut self, shape: LoadShape) -> u8 {
        match shape {
            LoadShape::Cube => self.cube.take(),
            LoadShape::Sphere => self.sphere.take(),
        }
    }

    fn static_pulley(&mut self, solid: bool) -> u8 {
        if solid {
            self.static_solid.take()
        } else {
            self.static_hollow.take()
        }
    }
}

fn color_name(id: u8) -> &'static str {
    palette_color(id).map_or("Gray", |c| c.name)
}

fn random_shape(rng: &mut ChaCha8Rng) -> LoadShape {
    if rng.random::<f64>() < 0.5 {
        LoadShape::Cube
    } else {
        LoadShape::Sphere
    }
}

/// Layout attempts before giving up (the release needs about 6.5 per accepted scene).
pub const MAX_LAYOUT_ATTEMPTS: u32 = 10_000;

/// Samples layouts until one passes the release's load-count condition and our checks.
/// Returns the layout and the number of rejected attempts; `None` if none passed within
/// [`MAX_LAYOUT_ATTEMPTS`].
pub fn sample_layout(rng: &mut ChaCha8Rng) -> Option<(Layout, u32)> {
    let luck: f64 = rng.random();
    let mut rejected = 0;
    while rejected < MAX_LAYOUT_ATTEMPTS {
        if let Ok(layout) = try_layout(rng) {
            let loads_per_group: Vec<usize> = layout
                .related_groups
                .iter()
                .map(|group| group.iter().filter(|n| is_load_name(n)).count())
                .collect();
            let two = loads_per_group.iter().filter(|&&n| n == 2).count();
            let one = loads_per_group.iter().filter(|&&n| n == 1).count();
            let accepted = if luck <= 0.7 {
                two >= 2
            } else if luck >= 0.9 {
                two > 0 || one > 1
            } else {
                true
            };
            if accepted {
                let mut layout = layout;
                rearrange(&mut layout, rng);
                sample_masses(&mut layout, rng);
                layout.meta = build_meta(&layout, &layout.meta);
                return Some((layout, rejected));
            }
        }
        rejected += 1;
    }
    None
}

fn is_load_name(name: &str) -> bool {
    name.ends_with(" Cube") || name.ends_with(" Sphere")
}

/// Why a sampled layout was dropped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Rejection {
    /// Ropes merged end to end or closed loops (not modelled).
    Merged,
    /// Two objects got the same name (the release loses such scenes too).
    DuplicateName(String),
    /// A group without elements, or a cable whose pulleys are missing.
    Malformed,
}

/// The walk of `SampleScheme`.
struct Scheme {
    states: Vec<Vec<Slot>>,
    divisions: Vec<Division>,
    connects: Vec<Connect>,
}

fn sample_scheme(rng: &mut ChaCha8Rng) -> Scheme {
    let layers: i32 = rng.random_range(0..2);
    let mut states: Vec<Vec<Slot>> = Vec::new();
    let mut divisions: Vec<Division> = Vec::new();
    let mut connects: Vec<Connect> = Vec::new();
    let mut depth: i32 = 0;
    let mut pointer: i64 = 0;
    let mut last = UPPER;
    let mut next_x: i32 = 0;
    let mut last_x: i32 = 0;
    let mut last_depth: i32 = 0;
    let mut total: i32 = 0;
    let mut remaining: i32 = 0;
    let mut done = false;
    let big = |rng: &mut ChaCha8Rng| rng.random::<f64>() < BIG_PULLEY_P;
    loop {
        let step = if depth % 2 == 0 { 1 } else { -1 };
        let mut columns: i32 = if layers == 0 {
            rng.random_range(3..6)
        } else {
            rng.random_range(2..4)
        };
        if depth == 1 && columns < remaining {
            columns = remaining;
        }
        let mut state: Vec<Slot> = Vec::new();
        let slot = |state: i32, position: i32, big: bool, x: i32, depth: i32| Slot {
            state,
            position,
            big,
            x,
            depth,
            division: None,
        };
        for i in 0..columns {
            if remaining == 0 {
                remaining = rng.random_range(2..5);
                if depth == layers && remaining + i >= columns {
                    remaining = columns - i;
                }
                if depth > layers {
                    done = true;
                    break;
                }
                total = remaining;
                let u: f64 = rng.random();
                if u < UP_START_P {
                    divisions.push(Division {
                        kind: END_STATIC_CEIL,
                        x: next_x,
                        depth,
                        target: None,
                    });
                    last = UPPER;
                } else if u - UP_START_P < LOW_START_P {
                    divisions.push(Division {
                        kind: END_STATIC_FLOO,
                        x: next_x,
                        depth,
                        target: None,
                    });
                    last = LOWER;
                } else {
                    divisions.push(Division {
                        kind: END_DYNAMIC_WAIT,
                        x: next_x,
                        depth,
                        target: None,
                    });
                    let mut wait = slot(END_DYNAMIC_WAIT, LOWER_DYN, false, next_x, depth);
                    wait.division = Some(divisions.len() - 1);
                    state.push(wait);
                    next_x += step;
                    last = LOWER_DYN;
                }
            }
            pointer -= 1;
            if i == 0 || i == columns - 1 {
                // Edge columns are static ("avoid unstable layout").
                if rng.random::<f64>() < 0.5 {
                    last = UPPER_FLAT;
                    state.push(slot(STATICS, UPPER_FLAT, big(rng), next_x, depth));
                } else {
                    last = LOWER_FLAT;
                    state.push(slot(STATICS, LOWER, big(rng), next_x, depth));
                }
            } else if is_upper(last) {
                let p: f64 = rng.random();
                if last == UPPER && p < STATIC_FLAT_P {
                    last = UPPER_FLAT;
                    state.push(slot(STATICS, UPPER_FLAT, big(rng), next_x, depth));
                } else if rng.random::<f64>() < LOW_STATIC_P || last == UPPER_DYN {
                    last = LOWER;
                    state.push(slot(STATICS, LOWER, big(rng), next_x, depth));
                } else {
                    last = LOWER_DYN;
                    state.push(slot(DYNAMIC_WAIT, LOWER_DYN, big(rng), next_x, depth));
                }
            } else {
                let p: f64 = rng.random();
                if last == LOWER && p < STATIC_FLAT_P {
                    last = LOWER_FLAT;
                    state.push(slot(STATICS, LOWER_FLAT, big(rng), next_x, depth));
                } else {
                    // The slot "above" is found by list index into the previous layer, walked
                    // backwards, as the release does (not by column).
                    let previous_layer = usize::try_from(depth - 1).ok();
                    let above = usize::try_from(pointer)
                        .ok()
                        .zip(previous_layer)
                        .and_then(|(p, layer)| states.get(layer).map(|slots| (slots, p)))
                        .and_then(|(slots, p)| slots.get(p).map(|s| (p, s.clone())));
                    let eligible = above.as_ref().is_some_and(|(_, a)| {
                        a.position == LOWER_DYN
                            && (a.state == DYNAMIC_WAIT || a.state == END_DYNAMIC_WAIT)
                            && last != LOWER_DYN
                    });
                    if let (true, Some((index, a)), Some(layer)) = (eligible, above, previous_layer)
                    {
                        let q: f64 = rng.random();
                        if a.state == DYNAMIC_WAIT {
                            if q < UP_WITH_UPPER_DYN_STATIC_P {
                                last = UPPER;
                                state.push(slot(STATICS, UPPER, big(rng), next_x, depth));
                                states[layer][index].state = DYNAMIC_WITH_LOAD;
                            } else if total > remaining
                                && q - UP_WITH_UPPER_DYN_STATIC_P < UP_WITH_UPPER_DYN_END_P
                            {
                                remaining = 1;
                                last = END_DYNAMIC_PULY;
                                states[layer][index].state = DYNAMIC_WITH_END;
                                divisions.push(Division {
                                    kind: END_DYNAMIC_PULY,
                                    x: last_x,
                                    depth: last_depth,
                                    target: Some((a.x, a.depth)),
                                });
                            } else {
                                states[layer][index].state = DYNAMIC_WITH_DYN;
                                last = UPPER_DYN;
                                state.push(slot(
                                    DYNAMIC_WITH_DYN,
                                    UPPER_DYN,
                                    big(rng),
                                    next_x,
                                    depth,
                                ));
                                connects.push(Connect {
                                    upper: (a.x, a.depth),
                                    lower: (next_x, depth),
                                });
                            }
                        } else if q < UP_WITH_UPPER_DYN_STATIC_P {
                            last = UPPER;
                            states[layer][index].state = END_DYNAMIC_LOAD;
                            state.push(slot(STATICS, UPPER, big(rng), next_x, depth));
                            if let Some(division) = a.division {
                                divisions[division].kind = END_DYNAMIC_LOAD;
                            }
                        } else if total > remaining
                            && q - UP_WITH_UPPER_DYN_STATIC_P < UP_WITH_UPPER_DYN_END_P
                        {
                            // Two ropes merged end to end: not modelled; marked for rejection.
                            remaining = 1;
                            states[layer][index].state = END_DYNAMIC_END;
                            if let Some(division) = a.division {
                                divisions[division].kind = END_DYNAMIC_END;
                            }
                            divisions.push(Division {
                                kind: END_DYNAMIC_END,
                                x: last_x,
                                depth: last_depth,
                                target: None,
                            });
                            last = END_DYNAMIC_END;
                        } else {
                            states[layer][index].state = END_DYNAMIC_PULY;
                            last = UPPER_DYN;
                            if let Some(division) = a.division {
                                divisions[division].kind = END_DYNAMIC_PULY;
                                divisions[division].target = Some((next_x, depth));
                            }
                            state.push(slot(DYNAMIC_WITH_END, UPPER_DYN, big(rng), next_x, depth));
                        }
                    } else {
                        state.push(slot(STATICS, UPPER, big(rng), next_x, depth));
                        last = UPPER;
                    }
                }
            }
            last_x = next_x;
            last_depth = depth;
            next_x += step;
            remaining -= 1;
            if remaining == 0 {
                if last == END_DYNAMIC_END || last == END_DYNAMIC_PULY {
                    // The rope ended by joining something.
                } else if is_upper(last) {
                    if rng.random::<f64>() < LOW_END_STATIC_P {
                        divisions.push(Division {
                            kind: END_STATIC_FLOO,
                            x: last_x,
                            depth: last_depth,
                            target: None,
                        });
                    } else {
                        divisions.push(Division {
                            kind: END_DYNAMIC_WAIT,
                            x: last_x,
                            depth: last_depth,
                            target: None,
                        });
                        let mut wait = slot(END_DYNAMIC_WAIT, LOWER_DYN, false, next_x, depth);
                        wait.division = Some(divisions.len() - 1);
                        state.push(wait);
                        next_x += step;
                    }
                } else {
                    divisions.push(Division {
                        kind: END_STATIC_CEIL,
                        x: last_x,
                        depth: last_depth,
                        target: None,
                    });
                }
            }
        }
        last_depth = depth;
        next_x -= step;
        if done {
            if !state.is_empty() {
                states.push(state);
            }
            break;
        }
        pointer = i64::try_from(state.len()).unwrap_or(0);
        states.push(state);
        depth += 1;
    }
    Scheme {
        states,
        divisions,
        connects,
    }
}

/// One layout attempt: the walk, its poses and terminals, the dynamic-node limit, names and
/// groups.
fn try_layout(rng: &mut ChaCha8Rng) -> Result<Layout, Rejection> {
    let scheme = sample_scheme(rng);
    if !scheme.divisions.len().is_multiple_of(2) {
        return Err(Rejection::Malformed);
    }
    if scheme.divisions.iter().any(|d| d.kind == END_DYNAMIC_END) {
        return Err(Rejection::Merged);
    }
    let mut pools = Pools::new(rng);
    // Poses: each rope collects the pulley slots of the walk, in list order, up to its end.
    let mut ropes: Vec<Vec<Element>> = Vec::new();
    let flat: Vec<(usize, usize, &Slot)> = scheme
        .states
        .iter()
        .enumerate()
        .flat_map(|(layer, slots)| {
            slots
                .iter()
                .enumerate()
                .map(move |(column, slot)| (column, layer, slot))
        })
        .collect();
    let mut cursor = 0;
    for pair in scheme.divisions.chunks(2) {
        let end = &pair[1];
        let mut path = Vec::new();
        loop {
            let Some(&(column, layer, slot)) = flat.get(cursor) else {
                return Err(Rejection::Malformed);
            };
            cursor += 1;
            if slot.state <= STATICS {
                let row = slot.position;
                let y = BASE_Y
                    - if row % 2 == 0 { 0.0 } else { Y_STEP }
                    - 2.0 * f64::from(slot.depth) * LAYER_STEP;
                let x = BASE_X + f64::from(slot.x) * X_STEP;
                let dynamic = slot.state != STATICS;
                let (load_shape, load_color) =
                    if slot.state == DYNAMIC_WITH_LOAD || slot.state == DYNAMIC_WAIT {
                        let shape = random_shape(rng);
                        (Some(shape), Some(pools.load(shape)))
                    } else {
                        (None, None)
                    };
                let color = if dynamic {
                    if slot.big {
                        pools.movable_hollow.take()
                    } else {
                        pools.movable_solid.take()
                    }
                } else {
                    pools.static_pulley(!slot.big)
                };
                path.push(Element {
                    kind: if dynamic {
                        ElementKind::MovablePulley
                    } else {
                        ElementKind::StaticPulley
                    },
                    code: slot.state,
                    name: String::new(),
                    position: [x, y],
                    grid: Some((slot.depth, slot.x)),
                    in_states: Some((column, layer)),
                    solid: !slot.big,
                    row,
                    color,
                    load_shape,
                    load_color,
                    hanging: None,
                    target: None,
                });
            }
            if slot.x == end.x && slot.depth == end.depth {
                break;
            }
        }
        if path.is_empty() {
            return Err(Rejection::Malformed);
        }
        ropes.push(path);
    }
    // Terminals.
    for (index, division) in scheme.divisions.iter().enumerate() {
        let rope = index / 2;
        let at_start = index % 2 == 0;
        let code = if division.kind == END_DYNAMIC_WAIT {
            END_DYNAMIC_LOAD
        } else {
            division.kind
        };
        let adjacent = if at_start {
            ropes[rope].first()
        } else {
            ropes[rope].last()
        }
        .cloned()
        .ok_or(Rejection::Malformed)?;
        let direction = f64::from(if division.depth % 2 == 0 { -1 } else { 1 })
            * if at_start { 1.0 } else { -1.0 };
        let x = adjacent.position[0] + 0.5 * X_STEP * direction * RADIUS_SCALE;
        let mut y =
            adjacent.position[1] + if adjacent.row % 2 == 0 { -1.0 } else { 1.0 } * 0.5 * Y_STEP;
        let (kind, color, load_shape) = match code {
            END_STATIC_CEIL => {
                y += Y_STEP * CEIL_FLOOR_SCALE;
                (
                    ElementKind::FixedPoint(true),
                    pools.fixed_point.take(),
                    None,
                )
            }
            END_STATIC_FLOO => {
                y -= Y_STEP * CEIL_FLOOR_SCALE;
                (
                    ElementKind::FixedPoint(false),
                    pools.fixed_point.take(),
                    None,
                )
            }
            END_DYNAMIC_LOAD => {
                y = adjacent.position[1] - OBJ_POS_SCALE * Y_STEP;
                let shape = random_shape(rng);
                (ElementKind::Load, pools.load(shape), Some(shape))
            }
            END_DYNAMIC_PULY => {
                y = adjacent.position[1] - OBJ_POS_SCALE * Y_STEP;
                (ElementKind::TiedToPulley, 0, None)
            }
            _ => return Err(Rejection::Malformed),
        };
        let element = Element {
            kind,
            code,
            name: String::new(),
            position: [x, y],
            grid: None,
            in_states: None,
            solid: false,
            row: adjacent.row,
            color,
            load_shape,
            load_color: None,
            hanging: None,
            target: division.target,
        };
        if at_start {
            ropes[rope].insert(0, element);
        } else {
            ropes[rope].push(element);
        }
    }
    // At most two dynamic nodes per cable: surplus ones become static pulleys or fixed points.
    let mut dynamic_indices: Vec<Vec<usize>> = Vec::new();
    for path in &mut ropes {
        let last = path.len() - 1;
        let mut nodes: Vec<usize> = (1..last).filter(|&i| path[i].code < STATICS).collect();
        for end in [0, last] {
            if matches!(path[end].code, END_DYNAMIC_LOAD | END_DYNAMIC_PULY) {
                nodes.push(end);
            }
        }
        let mut attempts = 0;
        while nodes.len() > MAX_DYNAMIC_NODES_PER_CABLE && attempts < 50 {
            attempts += 1;
            let pick = rng.random_range(0..nodes.len());
            let index = nodes[pick];
            if path[index].code == END_DYNAMIC_PULY {
                continue;
            }
            let element = &mut path[index];
            if index == 0 || index == last {
                let floor = element.row / 2 == 0;
                element.code = if floor {
                    END_STATIC_FLOO
                } else {
                    END_STATIC_CEIL
                };
                element.kind = ElementKind::FixedPoint(!floor);
                element.position[1] += OBJ_POS_SCALE * Y_STEP
                    + if element.row % 2 == 0 { -1.0 } else { 1.0 } * 0.5 * Y_STEP
                    + if floor { -1.0 } else { 1.0 } * CEIL_FLOOR_SCALE * Y_STEP;
                element.color = pools.fixed_point.take();
                element.load_shape = None;
            } else {
                element.code = STATICS;
                element.kind = ElementKind::StaticPulley;
                element.color = pools.static_pulley(element.solid);
                // The release keeps the stale load keys in metaSampling; the load is gone.
            }
            nodes.remove(pick);
        }
        dynamic_indices.push(nodes);
    }
    name_and_group(ropes, dynamic_indices, &scheme.connects, &mut pools)
}

/// Names every object, builds the cables and the related groups.
fn name_and_group(
    mut paths: Vec<Vec<Element>>,
    dynamic_indices: Vec<Vec<usize>>,
    connects: &[Connect],
    pools: &mut Pools,
) -> Result<Layout, Rejection> {
    // Object names.
    for path in &mut paths {
        for element in path.iter_mut() {
            element.name = match element.kind {
                ElementKind::StaticPulley | ElementKind::MovablePulley => {
                    let (layer, column) = element.grid.unwrap_or((0, 0));
                    format!(
                        "{} {} {} Pulley ({layer} {column})",
                        color_name(element.color),
                        if element.solid { "Solid" } else { "Hollow" },
                        if element.kind == ElementKind::StaticPulley {
                            "Static"
                        } else {
                            "Dynamic"
                        }
                    )
                }
                ElementKind::FixedPoint(_) => format!("{} Fixed Point", color_name(element.color)),
                ElementKind::Load => format!(
                    "{} {}",
                    color_name(element.color),
                    element.load_shape.unwrap_or(LoadShape::Cube).word()
                ),
                ElementKind::TiedToPulley => String::new(),
            };
        }
    }
    // Ropes: each main cable, then its load connections in element order.
    let mut ropes = Vec::new();
    for (path, dynamic) in paths.into_iter().zip(dynamic_indices) {
        let color = pools.rope.take();
        let name = format!("{} Rope", color_name(color));
        let mut path = path;
        for element in &mut path {
            let carries = element.kind == ElementKind::MovablePulley
                && matches!(element.code, DYNAMIC_WAIT | DYNAMIC_WITH_LOAD);
            if carries {
                let shape = element.load_shape.unwrap_or(LoadShape::Cube);
                let load = format!(
                    "{} {}",
                    color_name(element.load_color.unwrap_or(0)),
                    shape.word()
                );
                let connection = format!("{} Rope", color_name(pools.rope.take()));
                element.hanging = Some((load, connection));
            }
        }
        ropes.push(LayoutRope {
            name,
            color,
            path,
            dynamic_indices: dynamic,
        });
    }
    // Tied ends find their pulley by grid slot.
    let by_grid = |ropes: &[LayoutRope], target: (i32, i32)| -> Option<String> {
        ropes
            .iter()
            .flat_map(|r| r.path.iter())
            .find(|e| e.is_pulley() && e.grid == Some((target.1, target.0)))
            .map(|e| e.name.clone())
    };
    let mut tied: Vec<(usize, bool, String)> = Vec::new();
    for (index, rope) in ropes.iter().enumerate() {
        for (at_start, element) in [(true, rope.path.first()), (false, rope.path.last())] {
            if let Some(element) = element
                && element.kind == ElementKind::TiedToPulley
            {
                let target = element.target.ok_or(Rejection::Malformed)?;
                tied.push((
                    index,
                    at_start,
                    by_grid(&ropes, target).ok_or(Rejection::Malformed)?,
                ));
            }
        }
    }
    let mut cables = Vec::new();
    for connect in connects {
        let upper = by_grid(&ropes, connect.upper).ok_or(Rejection::Malformed)?;
        let lower = by_grid(&ropes, connect.lower).ok_or(Rejection::Malformed)?;
        let color = pools.rope.take();
        cables.push(Cable {
            name: format!("{} Rope", color_name(color)),
            upper,
            lower,
        });
    }
    // Duplicate names lose the scene in the release (a dictionary throws).
    let mut seen: Vec<String> = Vec::new();
    let mut check = |name: &str| -> Result<(), Rejection> {
        if name.is_empty() {
            return Ok(());
        }
        if seen.iter().any(|s| s == name) {
            return Err(Rejection::DuplicateName(name.to_string()));
        }
        seen.push(name.to_string());
        Ok(())
    };
    for rope in &ropes {
        check(&rope.name)?;
        for element in &rope.path {
            check(&element.name)?;
            if let Some((load, connection)) = &element.hanging {
                check(load)?;
                check(connection)?;
            }
        }
    }
    for cable in &cables {
        check(&cable.name)?;
    }
    // Per-rope lists (`AnswerRelations`).
    let mut lists: Vec<Vec<String>> = Vec::new();
    for rope in &ropes {
        let mut list = Vec::new();
        let last = rope.path.len() - 1;
        for element in &rope.path[1..last] {
            list.push(rope.name.clone());
            list.push(element.name.clone());
            if let Some((load, connection)) = &element.hanging {
                list.push(connection.clone());
                list.push(load.clone());
            }
        }
        list.push(rope.name.clone());
        if !rope.path[0].name.is_empty() {
            list.insert(0, rope.path[0].name.clone());
        }
        if !rope.path[last].name.is_empty() {
            list.push(rope.path[last].name.clone());
        }
        lists.push(list);
    }
    for (rope, at_start, target) in &tied {
        if *at_start {
            lists[*rope].insert(0, target.clone());
        } else {
            lists[*rope].push(target.clone());
        }
    }
    // Groups: ropes joined by a cable between movable pulleys, or by an end tied to a movable
    // pulley, are one group.
    let rope_of = |name: &str| lists.iter().position(|l| l.iter().any(|n| n == name));
    let dynamic = |name: &str| name.contains("Dynamic");
    let mut label: Vec<usize> = (0..ropes.len()).collect();
    let find = |label: &mut [usize], i: usize| -> usize {
        let mut root = i;
        while label[root] != root {
            root = label[root];
        }
        label[i] = root;
        root
    };
    let mut joined_order: Vec<usize> = Vec::new();
    let union = |label: &mut Vec<usize>, a: usize, b: usize, order: &mut Vec<usize>| {
        for r in [a, b] {
            if !order.contains(&r) {
                order.push(r);
            }
        }
        let (ra, rb) = (find(label, a), find(label, b));
        if ra != rb {
            label[rb] = ra;
        }
    };
    let mut cable_group: Vec<Option<usize>> = Vec::new();
    for cable in &cables {
        let a = rope_of(&cable.upper).ok_or(Rejection::Malformed)?;
        let b = rope_of(&cable.lower).ok_or(Rejection::Malformed)?;
        match (dynamic(&cable.upper), dynamic(&cable.lower)) {
            (true, true) => {
                union(&mut label, a, b, &mut joined_order);
                cable_group.push(Some(a));
            }
            (true, false) => cable_group.push(Some(a)),
            (false, true) => cable_group.push(Some(b)),
            (false, false) => cable_group.push(None),
        }
    }
    for (rope, _, target) in &tied {
        if dynamic(target) {
            let other = rope_of_excluding(&lists, target, *rope).ok_or(Rejection::Malformed)?;
            union(&mut label, *rope, other, &mut joined_order);
        }
    }
    let mut order = joined_order;
    for rope in 0..ropes.len() {
        if !order.contains(&rope) {
            order.push(rope);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_roots: Vec<usize> = Vec::new();
    for rope in order {
        let root = find(&mut label, rope);
        if let Some(g) = group_roots.iter().position(|&r| r == root) {
            groups[g].push(rope);
        } else {
            group_roots.push(root);
            groups.push(vec![rope]);
        }
    }
    let mut related_groups = Vec::new();
    let mut related_groups_in_rope = Vec::new();
    for (g, members) in groups.iter().enumerate() {
        let mut flat = Vec::new();
        let mut by_rope: IndexMap<String, Vec<String>> = IndexMap::new();
        for &rope in members {
            flat.extend(lists[rope].iter().cloned());
            let mut main = lists[rope].clone();
            for element in &ropes[rope].path {
                if let Some((load, connection)) = &element.hanging {
                    by_rope.insert(
                        connection.clone(),
                        vec![element.name.clone(), connection.clone(), load.clone()],
                    );
                    if let Some(at) = main.iter().position(|n| n == connection) {
                        main.remove(at);
                    }
                    if let Some(at) = main.iter().position(|n| n == load) {
                        main.remove(at);
                    }
                }
            }
            by_rope.insert(ropes[rope].name.clone(), main);
        }
        for (cable, group) in cables.iter().zip(&cable_group) {
            if group.is_some_and(|r| find(&mut label, r) == group_roots[g]) {
                by_rope.insert(
                    cable.name.clone(),
                    vec![cable.upper.clone(), cable.name.clone(), cable.lower.clone()],
                );
            }
        }
        related_groups.push(flat);
        related_groups_in_rope.push(by_rope);
    }
    for (cable, group) in cables.iter().zip(&cable_group) {
        if group.is_none() {
            related_groups.push(Vec::new());
            let mut by_rope = IndexMap::new();
            by_rope.insert(
                cable.name.clone(),
                vec![cable.upper.clone(), cable.name.clone(), cable.lower.clone()],
            );
            related_groups_in_rope.push(by_rope);
        }
    }
    if related_groups
        .iter()
        .zip(&related_groups_in_rope)
        .any(|(g, r)| g.is_empty() && r.is_empty())
    {
        return Err(Rejection::Malformed);
    }
    // Loads in `outputMass` order: hanging loads (rope by rope), then end loads.
    let mut loads: Vec<(String, f64)> = Vec::new();
    for rope in &ropes {
        for element in &rope.path {
            if let Some((load, _)) = &element.hanging {
                loads.push((load.clone(), world::MOVABLE_PULLEY_LOAD_MULTIPLIER));
            }
        }
    }
    for rope in &ropes {
        for element in [rope.path.first(), rope.path.last()].into_iter().flatten() {
            if element.kind == ElementKind::Load {
                loads.push((element.name.clone(), 1.0));
            }
        }
    }
    let mut positions: IndexMap<String, [f64; 2]> = IndexMap::new();
    let mut ids_in_pose: IndexMap<String, [usize; 2]> = IndexMap::new();
    for (r, rope) in ropes.iter().enumerate() {
        for (e, element) in rope.path.iter().enumerate() {
            if element.name.is_empty() {
                continue;
            }
            positions
                .entry(element.name.clone())
                .or_insert(element.position);
            ids_in_pose.entry(element.name.clone()).or_insert([r, e]);
            if let Some((load, _)) = &element.hanging {
                positions
                    .entry(load.clone())
                    .or_insert([element.position[0], element.position[1] - 0.5 * Y_STEP]);
                ids_in_pose.entry(load.clone()).or_insert([r, e]);
            }
        }
    }
    let meta = json!({
        "connection": connects.iter().map(|c| json!({
            "x1": c.upper.0, "y1": c.upper.1, "x2": c.lower.0, "y2": c.lower.1,
        })).collect::<Vec<_>>(),
    });
    Ok(Layout {
        ropes,
        cables,
        related_groups,
        related_groups_in_rope,
        masses_kg: vec![0.0; loads.len()],
        loads,
        positions,
        ids_in_pose,
        meta,
    })
}

fn rope_of_excluding(lists: &[Vec<String>], name: &str, excluded: usize) -> Option<usize> {
    lists
        .iter()
        .enumerate()
        .find(|(i, l)| *i != excluded && l.iter().any(|n| n == name))
        .map(|(i, _)| i)
}

/// Moves whole groups apart (`RearrangeObjects`): always when two groups come closer than 4
/// units, otherwise with probability ½; groups are shuffled left to right with 7-unit gaps and
/// placed at random heights in the scene's height band, keeping the overall centre.
fn rearrange(layout: &mut Layout, rng: &mut ChaCha8Rng) {
    // Layout groups: non-rope names per related group, merged when they share a name.
    let mut groups: Vec<Vec<String>> = Vec::new();
    for group in &layout.related_groups {
        let names: Vec<String> = group
            .iter()
            .filter(|n| !n.ends_with(" Rope") && layout.positions.contains_key(*n))
            .cloned()
            .collect();
        if names.is_empty() {
            continue;
        }
        match groups
            .iter()
            .position(|g| g.iter().any(|n| names.contains(n)))
        {
            Some(g) => {
                for name in names {
                    if !groups[g].contains(&name) {
                        groups[g].push(name);
                    }
                }
            }
            None => groups.push(names),
        }
    }
    if groups.len() < 2 {
        return;
    }
    let position = |name: &String| layout.positions.get(name).copied().unwrap_or([0.0, 0.0]);
    let mut close = false;
    for (a, first) in groups.iter().enumerate() {
        for second in &groups[a + 1..] {
            for p in first {
                for q in second {
                    let (pa, pb) = (position(p), position(q));
                    if (pa[0] - pb[0]).hypot(pa[1] - pb[1]) < MIN_DISTANCE_BETWEEN_GROUPS {
                        close = true;
                    }
                }
            }
        }
    }
    let random_layout = if rng.random::<f64>() < RANDOM_LAYOUT_P {
        true
    } else {
        close
    };
    if !random_layout {
        return;
    }
    let bounds = |names: &Vec<String>| {
        let mut low = [f64::INFINITY; 2];
        let mut high = [f64::NEG_INFINITY; 2];
        for name in names {
            let p = position(name);
            for axis in 0..2 {
                low[axis] = low[axis].min(p[axis]);
                high[axis] = high[axis].max(p[axis]);
            }
        }
        (low, high)
    };
    let boxes: Vec<([f64; 2], [f64; 2])> = groups.iter().map(bounds).collect();
    let mut order: Vec<usize> = (0..groups.len()).collect();
    order.shuffle(rng);
    let mut targets = vec![[0.0; 2]; groups.len()];
    let mut base = 0.0;
    for &g in &order {
        let width = boxes[g].1[0] - boxes[g].0[0];
        targets[g][0] = base + width / 2.0;
        base += width + REARRANGED_GROUP_GAP;
    }
    let top = boxes
        .iter()
        .map(|b| b.1[1])
        .fold(f64::NEG_INFINITY, f64::max);
    let bottom = boxes.iter().map(|b| b.0[1]).fold(f64::INFINITY, f64::min);
    let band = top - bottom;
    for (g, target) in targets.iter_mut().enumerate() {
        let height = boxes[g].1[1] - boxes[g].0[1];
        let low = -band + height / 2.0;
        let high = -height / 2.0;
        target[1] = if high > low {
            rng.random_range(low..high)
        } else {
            low
        };
    }
    let union = |boxes: &[([f64; 2], [f64; 2])]| {
        let low = [
            boxes.iter().map(|b| b.0[0]).fold(f64::INFINITY, f64::min),
            boxes.iter().map(|b| b.0[1]).fold(f64::INFINITY, f64::min),
        ];
        let high = [
            boxes
                .iter()
                .map(|b| b.1[0])
                .fold(f64::NEG_INFINITY, f64::max),
            boxes
                .iter()
                .map(|b| b.1[1])
                .fold(f64::NEG_INFINITY, f64::max),
        ];
        [
            f64::midpoint(low[0], high[0]),
            f64::midpoint(low[1], high[1]),
        ]
    };
    let moved: Vec<([f64; 2], [f64; 2])> = boxes
        .iter()
        .zip(&targets)
        .map(|(b, t)| {
            let half = [(b.1[0] - b.0[0]) / 2.0, (b.1[1] - b.0[1]) / 2.0];
            (
                [t[0] - half[0], t[1] - half[1]],
                [t[0] + half[0], t[1] + half[1]],
            )
        })
        .collect();
    let original_centre = union(&boxes);
    let moved_centre = union(&moved);
    let delta = [
        original_centre[0] - moved_centre[0],
        original_centre[1] - moved_centre[1],
    ];
    for (g, names) in groups.iter().enumerate() {
        let centre = [
            f64::midpoint(boxes[g].0[0], boxes[g].1[0]),
            f64::midpoint(boxes[g].0[1], boxes[g].1[1]),
        ];
        let shift = [
            targets[g][0] - centre[0] + delta[0],
            targets[g][1] - centre[1] + delta[1],
        ];
        for name in names {
            if let Some(p) = layout.positions.get_mut(name) {
                p[0] += shift[0];
                p[1] += shift[1];
            }
            for rope in &mut layout.ropes {
                for element in &mut rope.path {
                    if element.name == *name {
                        element.position[0] += shift[0];
                        element.position[1] += shift[1];
                        if let Some((load, _)) = &element.hanging
                            && let Some(p) = layout.positions.get_mut(load)
                        {
                            p[0] += shift[0];
                            p[1] += shift[1];
                        }
                    }
                }
            }
        }
    }
}

/// The factual masses: each load draws from {0.15, 0.25, 0.20} kg; in 80% of scenes the draw is
/// repeated (up to 100 times) until min(n, 3) distinct values appear; then the multiplier.
fn sample_masses(layout: &mut Layout, rng: &mut ChaCha8Rng) {
    let count = layout.loads.len();
    let draw = |rng: &mut ChaCha8Rng| -> Vec<f64> {
        (0..count)
            .map(|_| LOAD_MASSES_KG[rng.random_range(0..LOAD_MASSES_KG.len())])
            .collect()
    };
    let mut masses = draw(rng);
    if rng.random::<f64>() > 0.2 {
        let wanted = count.min(3);
        for _ in 0..100 {
            let mut distinct = masses.clone();
            distinct.sort_by(f64::total_cmp);
            distinct.dedup();
            if distinct.len() >= wanted {
                break;
            }
            masses = draw(rng);
        }
    }
    layout.masses_kg = masses
        .iter()
        .zip(&layout.loads)
        .map(|(m, (_, multiplier))| m * multiplier)
        .collect();
}

/// `metaSamplingData` in the release's form.
fn build_meta(layout: &Layout, partial: &Value) -> Value {
    let rope_meta: Vec<Value> = layout
        .ropes
        .iter()
        .map(|rope| {
            Value::Array(
                rope.path
                    .iter()
                    .map(|e| {
                        let mut entry = serde_json::Map::new();
                        entry.insert("type".into(), json!(f64::from(e.code)));
                        entry.insert("x".into(), json!(e.position[0]));
                        entry.insert("y".into(), json!(e.position[1]));
                        entry.insert("z".into(), json!(0.0));
                        if let (Some((layer, column)), Some((col_state, layer_state))) =
                            (e.grid, e.in_states)
                        {
                            entry.insert("idx".into(), json!(f64::from(column)));
                            entry.insert("idy".into(), json!(f64::from(layer)));
                            entry.insert("idx_in_states".into(), json!(col_state as f64));
                            entry.insert("idy_in_states".into(), json!(layer_state as f64));
                            entry.insert("scale".into(), json!(if e.solid { 0.0 } else { 1.0 }));
                        }
                        entry.insert("position".into(), json!(f64::from(e.row)));
                        if let Some(shape) = e.load_shape {
                            entry.insert(
                                "loadShape".into(),
                                json!(if shape == LoadShape::Cube { 1.0 } else { 0.0 }),
                            );
                        }
                        if let Some(color) = e.load_color {
                            entry.insert("loadColor".into(), json!(f64::from(color)));
                        }
                        if e.kind != ElementKind::TiedToPulley {
                            entry.insert("color".into(), json!(f64::from(e.color)));
                        }
                        if let Some((x, y)) = e.target {
                            entry.insert("target_x".into(), json!(f64::from(x)));
                            entry.insert("target_y".into(), json!(f64::from(y)));
                        }
                        Value::Object(entry)
                    })
                    .collect(),
            )
        })
        .collect();
    json!({
        "metaSampling": rope_meta,
        "connection": partial.get("connection").cloned().unwrap_or(json!([])),
        "name2idsInPose": layout.ids_in_pose,
        "name2position": layout.positions,
        "dynamicObjectIndex": layout.ropes.iter().map(|r| r.dynamic_indices.clone()).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;

    #[test]
    fn layouts_follow_the_release_grammar_and_statistics() {
        let mut rng = seeded_rng(11);
        let mut movable = 0;
        let mut rope_counts = [0_usize; 5];
        let samples = 300;
        for _ in 0..samples {
            let (layout, _) = sample_layout(&mut rng).unwrap();
            rope_counts[layout.ropes.len().min(4)] += 1;
            for rope in &layout.ropes {
                assert!(rope.path.len() >= 3, "ends and at least one pulley");
                assert!(!rope.path[0].is_pulley() && !rope.path[rope.path.len() - 1].is_pulley());
                assert!(
                    rope.path[1..rope.path.len() - 1]
                        .iter()
                        .all(Element::is_pulley)
                );
                assert!(rope.dynamic_indices.len() <= 2);
                if rope.path.iter().any(|e| e.hanging.is_some()) {
                    movable += 1;
                }
            }
            // Every named object parses as a release name and every load has a mass.
            for group in &layout.related_groups {
                for name in group {
                    assert!(
                        crate::dataset::parse_rope_object_name(name).is_some(),
                        "{name}"
                    );
                }
            }
            assert_eq!(layout.masses_kg.len(), layout.loads.len());
            for ((name, multiplier), mass) in layout.loads.iter().zip(&layout.masses_kg) {
                let base = mass / multiplier;
                assert!(
                    LOAD_MASSES_KG.iter().any(|m| (m - base).abs() < 1e-12),
                    "{name}: {mass}"
                );
                assert!(layout.positions.contains_key(name));
            }
        }
        // The release's port gives 2 ropes in 78% of scenes and a movable pulley with a load in
        // 65%; the sampler should be in that neighbourhood.
        let two_ropes = f64::from(u32::try_from(rope_counts[2]).unwrap()) / f64::from(samples);
        assert!((0.6..0.95).contains(&two_ropes), "{rope_counts:?}");
        assert!(movable > samples / 3, "{movable}");
    }

    #[test]
    fn the_same_seed_gives_the_same_layout() {
        let (a, _) = sample_layout(&mut seeded_rng(5)).unwrap();
        let (b, _) = sample_layout(&mut seeded_rng(5)).unwrap();
        assert_eq!(a.related_groups, b.related_groups);
        assert_eq!(a.masses_kg, b.masses_kg);
        assert_eq!(a.meta, b.meta);
    }
}
