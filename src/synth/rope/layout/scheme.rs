//! The walk of the release's `SampleScheme`: a serpentine walk over a grid of 1–2 layers that
//! places static pulleys, movable pulleys and rope ends slot by slot, drawing from the RNG in
//! the release's order.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::kind::{
    DYNAMIC_WAIT, DYNAMIC_WITH_DYN, DYNAMIC_WITH_END, DYNAMIC_WITH_LOAD, END_DYNAMIC_END,
    END_DYNAMIC_LOAD, END_DYNAMIC_PULY, END_DYNAMIC_WAIT, END_STATIC_CEIL, END_STATIC_FLOO,
    STATICS,
};
use super::{
    BIG_PULLEY_P, LOW_END_STATIC_P, LOW_START_P, LOW_STATIC_P, STATIC_FLAT_P, UP_START_P,
    UP_WITH_UPPER_DYN_END_P, UP_WITH_UPPER_DYN_STATIC_P,
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

/// A grid slot of the walk.
#[derive(Debug, Clone)]
pub(super) struct Slot {
    /// Slot state (a [`super::kind`] code).
    pub(super) state: i32,
    /// Row code (upper, lower, flat, dynamic).
    pub(super) position: i32,
    /// A hollow ("big") pulley.
    pub(super) big: bool,
    /// Column.
    pub(super) x: i32,
    /// Layer.
    pub(super) depth: i32,
    /// The rope end placed in this slot (index into the divisions).
    division: Option<usize>,
}

/// A rope end of the walk.
#[derive(Debug, Clone)]
pub(super) struct Division {
    /// What the end is (a [`super::kind`] code).
    pub(super) kind: i32,
    /// Column.
    pub(super) x: i32,
    /// Layer.
    pub(super) depth: i32,
    /// For an end tied to a pulley: the pulley's slot `(column, layer)`.
    pub(super) target: Option<(i32, i32)>,
}

/// A pulley–pulley cable between grid slots `(x, depth)`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Connect {
    /// The upper pulley's slot.
    pub(super) upper: (i32, i32),
    /// The lower pulley's slot.
    pub(super) lower: (i32, i32),
}

/// The walk of `SampleScheme`.
pub(super) struct Scheme {
    /// Per layer, its slots in walk order.
    pub(super) states: Vec<Vec<Slot>>,
    /// Rope ends in walk order, two per rope (start, end).
    pub(super) divisions: Vec<Division>,
    /// Pulley–pulley cables.
    pub(super) connects: Vec<Connect>,
}

/// The walk's loop state between slots: the release's loop variables, so the walk can be told
/// in steps (start a rope, place a slot, end a rope) that draw from the RNG in its order.
struct Walk {
    /// Layers below the first (0 or 1).
    layers: i32,
    /// The finished layers' slots.
    states: Vec<Vec<Slot>>,
    /// Rope ends so far.
    divisions: Vec<Division>,
    /// Pulley–pulley cables so far.
    connects: Vec<Connect>,
    /// The layer being walked.
    depth: i32,
    /// Index of the slot "above" in the previous layer's list, walked backwards.
    pointer: i64,
    /// Position code of the last slot (or the state the rope's start or end left).
    last: i32,
    /// Column of the next slot.
    next_x: i32,
    /// Column of the last slot.
    last_x: i32,
    /// Layer of the last slot.
    last_depth: i32,
    /// Slots the current rope was given when it started.
    total: i32,
    /// Slots the current rope still has to place.
    remaining: i32,
    /// The walk ran past its last layer.
    done: bool,
    /// Column direction of the layer being walked (+1 or −1).
    step: i32,
    /// Slots of the layer being walked.
    layer: Vec<Slot>,
}

/// Whether a new pulley is hollow ("big").
fn big(rng: &mut ChaCha8Rng) -> bool {
    rng.random::<f64>() < BIG_PULLEY_P
}

/// Walks the grid as `SampleScheme` does: layer by layer, alternating direction, ropes of two to
/// four slots, each started and ended by a fixed point or a rope end and joined to the layer
/// above where a movable pulley or rope end waits there.
pub(super) fn sample_scheme(rng: &mut ChaCha8Rng) -> Scheme {
    let layers: i32 = rng.random_range(0..2);
    let mut walk = Walk {
        layers,
        states: Vec::new(),
        divisions: Vec::new(),
        connects: Vec::new(),
        depth: 0,
        pointer: 0,
        last: UPPER,
        next_x: 0,
        last_x: 0,
        last_depth: 0,
        total: 0,
        remaining: 0,
        done: false,
        step: 1,
        layer: Vec::new(),
    };
    loop {
        walk.step = if walk.depth % 2 == 0 { 1 } else { -1 };
        let mut columns: i32 = if layers == 0 {
            rng.random_range(3..6)
        } else {
            rng.random_range(2..4)
        };
        if walk.depth == 1 && columns < walk.remaining {
            columns = walk.remaining;
        }
        walk.layer = Vec::new();
        for i in 0..columns {
            if walk.remaining == 0 && walk.start_rope(rng, i, columns) {
                break;
            }
            walk.pointer -= 1;
            if i == 0 || i == columns - 1 {
                walk.place_edge(rng);
            } else if is_upper(walk.last) {
                walk.place_after_upper(rng);
            } else {
                walk.place_after_lower(rng);
            }
            walk.finish_slot(rng);
        }
        walk.last_depth = walk.depth;
        walk.next_x -= walk.step;
        let state = std::mem::take(&mut walk.layer);
        if walk.done {
            if !state.is_empty() {
                walk.states.push(state);
            }
            break;
        }
        walk.pointer = i64::try_from(state.len()).unwrap_or(0);
        walk.states.push(state);
        walk.depth += 1;
    }
    Scheme {
        states: walk.states,
        divisions: walk.divisions,
        connects: walk.connects,
    }
}

impl Walk {
    /// A slot at the next column of the layer being walked.
    fn slot(&self, state: i32, position: i32, big: bool) -> Slot {
        Slot {
            state,
            position,
            big,
            x: self.next_x,
            depth: self.depth,
            division: None,
        }
    }

    /// Places a waiting rope end (a load unless something joins it) for the division just
    /// pushed, and moves to the next column.
    fn push_wait(&mut self) {
        let mut wait = self.slot(END_DYNAMIC_WAIT, LOWER_DYN, false);
        wait.division = Some(self.divisions.len() - 1);
        self.layer.push(wait);
        self.next_x += self.step;
    }

    /// Starts a rope at column `i` of a layer of `columns`: draws its length and its start (a
    /// ceiling point, a floor point, or a waiting end). Returns `true` when the walk is past its
    /// last layer instead.
    fn start_rope(&mut self, rng: &mut ChaCha8Rng, i: i32, columns: i32) -> bool {
        self.remaining = rng.random_range(2..5);
        if self.depth == self.layers && self.remaining + i >= columns {
            self.remaining = columns - i;
        }
        if self.depth > self.layers {
            self.done = true;
            return true;
        }
        self.total = self.remaining;
        let u: f64 = rng.random();
        if u < UP_START_P {
            self.divisions.push(Division {
                kind: END_STATIC_CEIL,
                x: self.next_x,
                depth: self.depth,
                target: None,
            });
            self.last = UPPER;
        } else if u - UP_START_P < LOW_START_P {
            self.divisions.push(Division {
                kind: END_STATIC_FLOO,
                x: self.next_x,
                depth: self.depth,
                target: None,
            });
            self.last = LOWER;
        } else {
            self.divisions.push(Division {
                kind: END_DYNAMIC_WAIT,
                x: self.next_x,
                depth: self.depth,
                target: None,
            });
            self.push_wait();
            self.last = LOWER_DYN;
        }
        false
    }

    /// Places a static pulley in an edge column ("avoid unstable layout"), upper flat or lower.
    fn place_edge(&mut self, rng: &mut ChaCha8Rng) {
        if rng.random::<f64>() < 0.5 {
            self.last = UPPER_FLAT;
            let slot = self.slot(STATICS, UPPER_FLAT, big(rng));
            self.layer.push(slot);
        } else {
            self.last = LOWER_FLAT;
            let slot = self.slot(STATICS, LOWER, big(rng));
            self.layer.push(slot);
        }
    }

    /// Places the slot after an upper one: an upper flat static pulley, a lower static pulley,
    /// or a movable pulley waiting below.
    fn place_after_upper(&mut self, rng: &mut ChaCha8Rng) {
        let p: f64 = rng.random();
        if self.last == UPPER && p < STATIC_FLAT_P {
            self.last = UPPER_FLAT;
            let slot = self.slot(STATICS, UPPER_FLAT, big(rng));
            self.layer.push(slot);
        } else if rng.random::<f64>() < LOW_STATIC_P || self.last == UPPER_DYN {
            self.last = LOWER;
            let slot = self.slot(STATICS, LOWER, big(rng));
            self.layer.push(slot);
        } else {
            self.last = LOWER_DYN;
            let slot = self.slot(DYNAMIC_WAIT, LOWER_DYN, big(rng));
            self.layer.push(slot);
        }
    }

    /// Places the slot after a lower one: a lower flat static pulley, something joined to the
    /// waiting slot "above" in the previous layer, or an upper static pulley.
    fn place_after_lower(&mut self, rng: &mut ChaCha8Rng) {
        let p: f64 = rng.random();
        if self.last == LOWER && p < STATIC_FLAT_P {
            self.last = LOWER_FLAT;
            let slot = self.slot(STATICS, LOWER_FLAT, big(rng));
            self.layer.push(slot);
        } else {
            // The slot "above" is found by list index into the previous layer, walked
            // backwards, as the release does (not by column).
            let previous_layer = usize::try_from(self.depth - 1).ok();
            let above = usize::try_from(self.pointer)
                .ok()
                .zip(previous_layer)
                .and_then(|(p, layer)| self.states.get(layer).map(|slots| (slots, p)))
                .and_then(|(slots, p)| slots.get(p).map(|s| (p, s.clone())));
            let eligible = above.as_ref().is_some_and(|(_, a)| {
                a.position == LOWER_DYN
                    && (a.state == DYNAMIC_WAIT || a.state == END_DYNAMIC_WAIT)
                    && self.last != LOWER_DYN
            });
            if let (true, Some((index, a)), Some(layer)) = (eligible, above, previous_layer) {
                let q: f64 = rng.random();
                if a.state == DYNAMIC_WAIT {
                    self.join_movable_pulley(rng, (layer, index), &a, q);
                } else {
                    self.join_rope_end(rng, (layer, index), &a, q);
                }
            } else {
                let slot = self.slot(STATICS, UPPER, big(rng));
                self.layer.push(slot);
                self.last = UPPER;
            }
        }
    }

    /// Under `a`, the movable pulley waiting at `(layer, index)` of the previous layer, with the
    /// draw `q`: a static pulley (`a` carries a load), this rope's end tied to `a`'s axle, or a
    /// movable pulley joined to `a` by a cable.
    fn join_movable_pulley(
        &mut self,
        rng: &mut ChaCha8Rng,
        (layer, index): (usize, usize),
        a: &Slot,
        q: f64,
    ) {
        if q < UP_WITH_UPPER_DYN_STATIC_P {
            self.last = UPPER;
            let slot = self.slot(STATICS, UPPER, big(rng));
            self.layer.push(slot);
            self.states[layer][index].state = DYNAMIC_WITH_LOAD;
        } else if self.total > self.remaining
            && q - UP_WITH_UPPER_DYN_STATIC_P < UP_WITH_UPPER_DYN_END_P
        {
            self.remaining = 1;
            self.last = END_DYNAMIC_PULY;
            self.states[layer][index].state = DYNAMIC_WITH_END;
            self.divisions.push(Division {
                kind: END_DYNAMIC_PULY,
                x: self.last_x,
                depth: self.last_depth,
                target: Some((a.x, a.depth)),
            });
        } else {
            self.states[layer][index].state = DYNAMIC_WITH_DYN;
            self.last = UPPER_DYN;
            let slot = self.slot(DYNAMIC_WITH_DYN, UPPER_DYN, big(rng));
            self.layer.push(slot);
            self.connects.push(Connect {
                upper: (a.x, a.depth),
                lower: (self.next_x, self.depth),
            });
        }
    }

    /// Under `a`, the rope end waiting at `(layer, index)` of the previous layer, with the draw
    /// `q`: a static pulley (`a` becomes a load), this rope's end merged with `a` (marked for
    /// rejection), or a movable pulley that `a` is tied to.
    fn join_rope_end(
        &mut self,
        rng: &mut ChaCha8Rng,
        (layer, index): (usize, usize),
        a: &Slot,
        q: f64,
    ) {
        if q < UP_WITH_UPPER_DYN_STATIC_P {
            self.last = UPPER;
            self.states[layer][index].state = END_DYNAMIC_LOAD;
            let slot = self.slot(STATICS, UPPER, big(rng));
            self.layer.push(slot);
            if let Some(division) = a.division {
                self.divisions[division].kind = END_DYNAMIC_LOAD;
            }
        } else if self.total > self.remaining
            && q - UP_WITH_UPPER_DYN_STATIC_P < UP_WITH_UPPER_DYN_END_P
        {
            // Two ropes merged end to end: not modelled; marked for rejection.
            self.remaining = 1;
            self.states[layer][index].state = END_DYNAMIC_END;
            if let Some(division) = a.division {
                self.divisions[division].kind = END_DYNAMIC_END;
            }
            self.divisions.push(Division {
                kind: END_DYNAMIC_END,
                x: self.last_x,
                depth: self.last_depth,
                target: None,
            });
            self.last = END_DYNAMIC_END;
        } else {
            self.states[layer][index].state = END_DYNAMIC_PULY;
            self.last = UPPER_DYN;
            if let Some(division) = a.division {
                self.divisions[division].kind = END_DYNAMIC_PULY;
                self.divisions[division].target = Some((self.next_x, self.depth));
            }
            let slot = self.slot(DYNAMIC_WITH_END, UPPER_DYN, big(rng));
            self.layer.push(slot);
        }
    }

    /// Moves past the slot just placed; when the rope has no slots left, ends it.
    fn finish_slot(&mut self, rng: &mut ChaCha8Rng) {
        self.last_x = self.next_x;
        self.last_depth = self.depth;
        self.next_x += self.step;
        self.remaining -= 1;
        if self.remaining == 0 {
            self.end_rope(rng);
        }
    }

    /// Ends the current rope: nothing when it ended by joining something, a floor point or a
    /// waiting end after an upper slot, a ceiling point after a lower one.
    fn end_rope(&mut self, rng: &mut ChaCha8Rng) {
        if self.last == END_DYNAMIC_END || self.last == END_DYNAMIC_PULY {
            // The rope ended by joining something.
        } else if is_upper(self.last) {
            if rng.random::<f64>() < LOW_END_STATIC_P {
                self.divisions.push(Division {
                    kind: END_STATIC_FLOO,
                    x: self.last_x,
                    depth: self.last_depth,
                    target: None,
                });
            } else {
                self.divisions.push(Division {
                    kind: END_DYNAMIC_WAIT,
                    x: self.last_x,
                    depth: self.last_depth,
                    target: None,
                });
                self.push_wait();
            }
        } else {
            self.divisions.push(Division {
                kind: END_STATIC_CEIL,
                x: self.last_x,
                depth: self.last_depth,
                target: None,
            });
        }
    }
}
