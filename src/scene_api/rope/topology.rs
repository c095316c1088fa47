//! Rope topology from pixels: which pulleys, loads and fixed points each rope runs through, in
//! which order, and on which side it passes each pulley, read from where the rope's pixels are.
//!
//! Every rope of the release is a chain: it starts at an end (a load, a fixed point, or a movable
//! pulley's hook), runs in straight segments tangent to the pulleys it wraps, and stops at another
//! end (`docs/data/rope.md`, names). So each hypothesis "the rope leaves node `a` on side `s_a` and
//! reaches node `b` on side `s_b`" is one straight segment whose geometry is fixed by the nodes'
//! centres and wrap radii; a hypothesis holds when the rope's pixels lie along it. [`read_ropes`]
//! searches the chains of segments the rope's pixels support and keeps, per rope, the one that
//! explains the most rope length. A segment that passes close by a pulley must wrap it, unless
//! the rope crosses itself there: the same rope wraps that pulley elsewhere and the segment
//! crosses another of its segments at an angle (seed 9473's video 9), or the pulley nearly
//! touches the one the rope just left and lies behind the segment's start (seed 6607's video 0).
//! No segment runs through a load it does not end at, and no chain ends on one of its own
//! segments (a candidate end where the rope's mask breaks off, seed 6607's videos 4 and 29).
//!
//! Input: the nodes (kind, centre on the scene plane `z = 0`, units), the number of ropes, and an
//! evidence function that says whether a rope's pixels cover a scene point (`None` when the point
//! is not observable, e.g. off-screen). Output: per rope, its path (node indices in order, with
//! the turn at each pulley it wraps) and how well the pixels support it, or nothing when no chain
//! is supported.

use crate::dataset::rope::world;
use crate::physics::rope::Turn;

/// What a node of the mechanism is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NodeKind {
    /// A static pulley; `solid` sets its wrap radius.
    StaticPulley { solid: bool },
    /// A movable pulley; `solid` sets its wrap radius.
    MovablePulley { solid: bool },
    /// A fixed point (rope end on the ceiling or floor).
    Anchor,
    /// A cube or sphere (rope end).
    Load,
}

impl NodeKind {
    /// The radius the rope wraps this node at when it passes it, units (`None`: a rope cannot
    /// pass it, only end at it).
    fn wrap_radius(self) -> Option<f64> {
        match self {
            NodeKind::StaticPulley { solid } | NodeKind::MovablePulley { solid } => {
                Some(world::wrap_radius(solid))
            }
            NodeKind::Anchor | NodeKind::Load => None,
        }
    }

    /// Whether a rope may end here: loads and fixed points, and a movable pulley's hook (a load
    /// hanging from a movable pulley on its own rope, or a rope tied to it).
    fn can_end(self) -> bool {
        !matches!(self, NodeKind::StaticPulley { .. })
    }

    /// Where a rope ending here is tied, relative to the node's centre, units.
    fn attachment(self) -> [f64; 2] {
        if self == NodeKind::Load {
            [0.0, world::LOAD_ATTACH_HEIGHT]
        } else {
            [0.0, 0.0]
        }
    }

    /// The radius round the centre inside which the node's body hides a rope tied to it, units:
    /// the disc of a pulley (its hook is inside), a load's half height, a fixed point's body.
    fn tied_hidden_radius(self) -> f64 {
        match self {
            NodeKind::StaticPulley { solid } | NodeKind::MovablePulley { solid } => {
                if solid {
                    world::SOLID_PULLEY_RADIUS
                } else {
                    world::HOLLOW_PULLEY_RADIUS
                }
            }
            NodeKind::Load => world::LOAD_HALF_HEIGHT + world::ROPE_RADIUS,
            NodeKind::Anchor => 0.6,
        }
    }

    /// The radius round the centre inside which the node's own body hides the rope, units.
    pub(crate) fn body_radius(self) -> f64 {
        match self {
            NodeKind::StaticPulley { solid } | NodeKind::MovablePulley { solid } => {
                let disc = if solid {
                    world::SOLID_PULLEY_RADIUS
                } else {
                    world::HOLLOW_PULLEY_RADIUS
                };
                disc.max(world::wrap_radius(solid)) + 2.0 * world::ROPE_RADIUS
            }
            NodeKind::Load => world::LOAD_HALF_HEIGHT * std::f64::consts::SQRT_2 + 0.1,
            NodeKind::Anchor => 0.6,
        }
    }
}

/// One pulley, load or fixed point, where perception put it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Node {
    /// What it is.
    pub kind: NodeKind,
    /// Centre on the scene plane, units.
    pub centre: [f64; 2],
}

/// One rope's chain as read from its pixels.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RopePath {
    /// Node indices from one end to the other.
    pub nodes: Vec<usize>,
    /// The turn at each node of `nodes` (`None` at the two ends).
    pub turns: Vec<Option<Turn>>,
    /// Samples along the segments that the rope's pixels cover.
    pub covered: usize,
    /// Samples along the segments that they do not cover.
    pub missed: usize,
    /// Of the covered samples, those on the detection's own mask (not only on pixels of the
    /// rope's colour elsewhere in the frame).
    pub on_mask: usize,
}

/// What a rope's pixels say about one scene point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sample {
    /// The detection's mask is there.
    OnMask,
    /// Only pixels of the rope's colour are there (another rope of that colour, or a stretch of
    /// this one the mask missed).
    OnColour,
    /// Nothing of the rope is there.
    Missed,
}

/// Samples of one segment hypothesis: covered (on mask or colour), missed, and on the mask; and
/// the pulleys it passes over, which the same rope must wrap elsewhere for the chain to hold.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
struct Support {
    covered: usize,
    missed: usize,
    on_mask: usize,
    crossed: Vec<usize>,
}

impl RopePath {
    /// A path with no samples counted yet.
    pub(crate) fn unscored(nodes: Vec<usize>, turns: Vec<Option<Turn>>) -> RopePath {
        RopePath {
            nodes,
            turns,
            covered: 0,
            missed: 0,
            on_mask: 0,
        }
    }

    /// The straight segments of the path, end to end, units.
    pub(crate) fn segments(&self, nodes: &[Node]) -> Vec<([f64; 2], [f64; 2])> {
        self.nodes
            .windows(2)
            .enumerate()
            .filter_map(|(i, pair)| {
                segment(
                    nodes.get(pair[0])?,
                    self.turns.get(i).copied().flatten(),
                    nodes.get(pair[1])?,
                    self.turns.get(i + 1).copied().flatten(),
                )
            })
            .collect()
    }

    /// Points along the whole rope, `spacing` apart: its straight segments and the arcs it wraps
    /// round each pulley between them (the shape the release's tracked rope particles have).
    pub(crate) fn polyline(&self, nodes: &[Node], spacing: f64) -> Vec<[f64; 2]> {
        let segments = self.segments(nodes);
        let mut points = Vec::new();
        for (index, (start, end)) in segments.iter().enumerate() {
            if index > 0
                && let (Some(&node), Some(Some(turn)), Some((_, previous_end))) = (
                    self.nodes.get(index),
                    self.turns.get(index),
                    segments.get(index - 1),
                )
                && let Some(node) = nodes.get(node)
                && let Some(radius) = node.kind.wrap_radius()
            {
                push_arc(
                    &mut points,
                    node.centre,
                    radius,
                    *previous_end,
                    *start,
                    *turn,
                    spacing,
                );
            }
            let length = distance(*start, *end);
            let count = pieces(length / spacing).max(1);
            for step in 0..=count {
                let t = step as f64 / count as f64;
                points.push(lerp(*start, *end, t));
            }
        }
        points
    }
}

fn push_arc(
    points: &mut Vec<[f64; 2]>,
    centre: [f64; 2],
    radius: f64,
    from: [f64; 2],
    to: [f64; 2],
    turn: Turn,
    spacing: f64,
) {
    let angle = |p: [f64; 2]| (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let (start, end) = (angle(from), angle(to));
    let mut sweep = end - start;
    // The rope goes round counter-clockwise (positive angles) for a counter-clockwise turn.
    match turn {
        Turn::CounterClockwise => {
            while sweep < 0.0 {
                sweep += std::f64::consts::TAU;
            }
        }
        Turn::Clockwise => {
            while sweep > 0.0 {
                sweep -= std::f64::consts::TAU;
            }
        }
    }
    let count = pieces(sweep.abs() * radius / spacing);
    for step in 1..count {
        let a = start + sweep * step as f64 / count as f64;
        points.push([centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]);
    }
}

/// How many pieces of at most one unit a length of `units` splits into (0 for non-finite or
/// non-positive lengths).
fn pieces(units: f64) -> usize {
    if units.is_finite() && units > 0.0 {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "positive and finite, and far below usize::MAX for scene lengths"
        )]
        let count = units.ceil().min(1e6) as usize;
        count
    } else {
        0
    }
}

/// Euclidean distance, units.
pub(crate) fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn lerp(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// The straight piece of rope from node `a` to node `b`: it leaves `a` tangent to its wrap circle
/// when `turn_a` is given (the rope goes round `a` that way), else from `a`'s attachment point,
/// and reaches `b` likewise. `None` when the circles overlap so that no such tangent exists.
///
/// With `s = +1` for a counter-clockwise turn (the centre on the rope's left) the tangent points
/// are `p = c − s·r·n`, `n` the left normal of the direction `d`; `c_b − c_a = L·d + k·n` with
/// `k = s_b·r_b − s_a·r_a`, so `d = (c_b − c_a)·(L − i·k) / |c_b − c_a|²` in complex numbers.
pub(crate) fn segment(
    a: &Node,
    turn_a: Option<Turn>,
    b: &Node,
    turn_b: Option<Turn>,
) -> Option<([f64; 2], [f64; 2])> {
    let circle = |node: &Node, turn: Option<Turn>| -> ([f64; 2], f64) {
        if let (Some(turn), Some(radius)) = (turn, node.kind.wrap_radius()) {
            (node.centre, turn.sign() * radius)
        } else {
            let offset = node.kind.attachment();
            (
                [node.centre[0] + offset[0], node.centre[1] + offset[1]],
                0.0,
            )
        }
    };
    let (ca, sa) = circle(a, turn_a);
    let (cb, sb) = circle(b, turn_b);
    let delta = [cb[0] - ca[0], cb[1] - ca[1]];
    let squared = delta[0] * delta[0] + delta[1] * delta[1];
    let k = sb - sa;
    let along_squared = squared - k * k;
    // Also refuses NaN.
    if along_squared.partial_cmp(&1e-9) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let along = along_squared.sqrt();
    // d = delta · (along − i·k) / |delta|².
    let direction = [
        (delta[0] * along + delta[1] * k) / squared,
        (delta[1] * along - delta[0] * k) / squared,
    ];
    let normal = [-direction[1], direction[0]];
    let start = [ca[0] - sa * normal[0], ca[1] - sa * normal[1]];
    let end = [cb[0] - sb * normal[0], cb[1] - sb * normal[1]];
    (start.iter().chain(&end).all(|v| v.is_finite())).then_some((start, end))
}

/// Clearance beyond its wrap radius within which a straight rope is taken to touch a pulley,
/// units. Measured on the generator's truth (seeds 9473 and 7321, 1,800 segment–pulley pairs):
/// a rope never passes a pulley it does not wrap closer than 2.09 units beyond its wrap radius,
/// while the straight line past a pulley a rope wraps only slightly (a few degrees) clears it by
/// up to 0.48; positions read from pixels are off by about 0.1–0.25. So 0.75 makes such a rope
/// wrap the pulley it passes and leaves a wide margin to every other pulley.
const GRAZE: f64 = 0.75;

fn distance_to_segment(point: [f64; 2], start: [f64; 2], end: [f64; 2]) -> f64 {
    let along = [end[0] - start[0], end[1] - start[1]];
    let squared = along[0] * along[0] + along[1] * along[1];
    let t = if squared > 0.0 {
        (((point[0] - start[0]) * along[0] + (point[1] - start[1]) * along[1]) / squared)
            .clamp(0.0, 1.0)
    } else {
        0.0
    };
    distance(point, lerp(start, end, t))
}

/// The pulleys other than its ends that the straight segment `start`–`end` from node `ends[0]` to
/// `ends[1]` passes within [`GRAZE`] of their wrap circle.
fn passed_pulleys(
    nodes: &[Node],
    ends: [usize; 2],
    (start, end): ([f64; 2], [f64; 2]),
) -> Vec<usize> {
    nodes
        .iter()
        .enumerate()
        .filter(|&(index, node)| {
            !ends.contains(&index)
                && node.kind.wrap_radius().is_some_and(|radius| {
                    distance_to_segment(node.centre, start, end) < radius + GRAZE
                })
        })
        .map(|(index, _)| index)
        .collect()
}

/// Distance from a load's centre within which a straight rope passes through the load, units:
/// three quarters of its half height (1), so that a strand passing beside a load (at least its
/// half width from the centre) is not taken for one through it when the centre read from pixels
/// is off by a few tenths.
const THROUGH_LOAD: f64 = 0.75 * world::LOAD_HALF_HEIGHT;

/// How densely segments are sampled against the pixels, units.
const SAMPLE_SPACING: f64 = 0.2;
/// Least share of a segment's observable samples the rope's pixels must cover.
const MIN_SEGMENT_COVERAGE: f64 = 0.75;
/// Observable samples under which a segment is too short to tell (a load just under its
/// pulley): it is accepted without evidence.
const MIN_SAMPLES: usize = 3;
/// Longest path searched, in nodes (the release's ropes have 2 to 7).
const MAX_PATH_NODES: usize = 9;

/// Samples of one segment the pixels cover and miss; `None` when they reject it.
fn segment_support(
    nodes: &[Node],
    [(from, from_wrapped), (to, to_wrapped)]: [(usize, bool); 2],
    (start, end): ([f64; 2], [f64; 2]),
    covers: &mut dyn FnMut([f64; 2]) -> Option<Sample>,
) -> Option<Support> {
    // A rope cannot pass through a pulley, and one it grazes turns it, unless the rope wraps
    // that pulley elsewhere: then this stretch lies over its own turn there (a rope crossing
    // itself, as in a figure of eight). The chain checks that when it is complete.
    let crossed = passed_pulleys(nodes, [from, to], (start, end));
    // Nor through a load: a stretch through a load's body that does not end there is read on to
    // a candidate end beyond the load (where a strand of the rope's own pixels breaks off), when
    // the rope ends at the load.
    let through_load = nodes.iter().enumerate().any(|(index, node)| {
        node.kind == NodeKind::Load
            && index != from
            && index != to
            && distance_to_segment(node.centre, start, end) < THROUGH_LOAD
    });
    if through_load {
        return None;
    }
    let length = distance(start, end);
    let count = pieces(length / SAMPLE_SPACING);
    let (mut covered, mut missed, mut on_mask) = (0, 0, 0);
    for step in 0..=count {
        let point = lerp(start, end, (step as f64 + 0.5) / (count as f64 + 1.0));
        // Samples where a node's body hides the rope tell nothing. A rope tied to an end (a
        // load's top, a movable pulley's hook) is seen right up to the body itself, so a short
        // rope hanging under a pulley keeps the few samples that show it.
        let hidden = nodes.iter().enumerate().any(|(index, node)| {
            let tied = (index == from && !from_wrapped) || (index == to && !to_wrapped);
            let reach = if tied {
                node.kind.tied_hidden_radius()
            } else if index == from || index == to {
                node.kind.body_radius()
            } else {
                node.kind.body_radius() * 0.8
            };
            distance(point, node.centre) < reach
        });
        if hidden {
            continue;
        }
        match covers(point) {
            Some(Sample::OnMask) => {
                covered += 1;
                on_mask += 1;
            }
            Some(Sample::OnColour) => covered += 1,
            Some(Sample::Missed) => missed += 1,
            None => {}
        }
    }
    let observed = covered + missed;
    if observed < MIN_SAMPLES {
        // Too short to see: a load hanging right under its pulley. Accept only short segments.
        return (length < 3.0).then_some(Support {
            crossed,
            ..Support::default()
        });
    }
    (covered as f64 >= MIN_SEGMENT_COVERAGE * observed as f64).then_some(Support {
        covered,
        missed,
        on_mask,
        crossed,
    })
}

/// Reads each rope's path: for every rope whose `seen` entry is true, the chain of supported
/// segments with the most samples on the rope's own mask, then the most covered samples (ties:
/// fewer missed, then fewer nodes, then the lower node indices), among chains that start and end
/// at nodes a rope can end at, wrap only pulleys in between, pass through no load and do not end
/// on their own segments; a rope not seen has no path (and costs no search). `covers(rope, point)`
/// says what rope `rope`'s pixels show at a scene point. The mask comes first because pixels of
/// the rope's colour elsewhere may be another rope's: a short white rope under a pulley would
/// otherwise be read along a long rope whose light strands look like it.
pub(crate) fn read_ropes(
    nodes: &[Node],
    seen: &[bool],
    covers: &mut dyn FnMut(usize, [f64; 2]) -> Option<Sample>,
) -> Vec<Option<RopePath>> {
    seen.iter()
        .enumerate()
        .map(|(rope, &seen)| {
            seen.then(|| read_rope(nodes, &mut |point| covers(rope, point)))
                .flatten()
        })
        .collect()
}

/// Turns a node can be passed with: both sides for pulleys, none for ends.
fn turn_options(kind: NodeKind) -> &'static [Option<Turn>] {
    if kind.wrap_radius().is_some() {
        &[Some(Turn::CounterClockwise), Some(Turn::Clockwise)]
    } else {
        &[None]
    }
}

fn read_rope(
    nodes: &[Node],
    covers: &mut dyn FnMut([f64; 2]) -> Option<Sample>,
) -> Option<RopePath> {
    // Support of every directed segment hypothesis, computed once: (from, turn at from, to,
    // turn at to) → (covered, missed). Ends are passed with no turn.
    type Key = (usize, u8, usize, u8);
    let code = |turn: Option<Turn>| match turn {
        None => 0,
        Some(Turn::CounterClockwise) => 1,
        Some(Turn::Clockwise) => 2,
    };
    let mut support: std::collections::BTreeMap<Key, Option<Support>> =
        std::collections::BTreeMap::new();
    let mut lookup = |from: usize, turn_from: Option<Turn>, to: usize, turn_to: Option<Turn>| {
        support
            .entry((from, code(turn_from), to, code(turn_to)))
            .or_insert_with(|| {
                let geometry = segment(&nodes[from], turn_from, &nodes[to], turn_to)?;
                let ends = [(from, turn_from.is_some()), (to, turn_to.is_some())];
                segment_support(nodes, ends, geometry, covers)
            })
            .clone()
    };
    let mut best: Option<RopePath> = None;
    for start in 0..nodes.len() {
        if !nodes[start].kind.can_end() {
            continue;
        }
        let mut path = RopePath::unscored(vec![start], vec![None]);
        extend(nodes, &mut path, &mut Vec::new(), &mut lookup, &mut best);
    }
    best
}

/// The support of a directed segment hypothesis (from, turn, to, turn): samples covered and
/// missed, or `None` when rejected.
type Lookup<'a> = dyn FnMut(usize, Option<Turn>, usize, Option<Turn>) -> Option<Support> + 'a;

/// Depth-first search from the path's last node; records every complete chain that beats `best`.
/// `crossed` holds the pulleys the path's segments pass over so far, each with the index of the
/// segment that passes it.
fn extend(
    nodes: &[Node],
    path: &mut RopePath,
    crossed: &mut Vec<(usize, usize)>,
    lookup: &mut Lookup<'_>,
    best: &mut Option<RopePath>,
) {
    let (Some(&last), Some(&last_turn)) = (path.nodes.last(), path.turns.last()) else {
        return;
    };
    if path.nodes.len() >= MAX_PATH_NODES {
        return;
    }
    for next in 0..nodes.len() {
        if path.nodes.contains(&next) {
            continue;
        }
        // Ending at `next`.
        if nodes[next].kind.can_end()
            && let Some(support) = lookup(last, last_turn, next, None)
        {
            let mut done = path.clone();
            done.nodes.push(next);
            done.turns.push(None);
            done.covered += support.covered;
            done.missed += support.missed;
            done.on_mask += support.on_mask;
            // A chain and its reverse are the same rope; keep the one that starts lower.
            if done.nodes.first() < done.nodes.last()
                && better(&done, best.as_ref())
                && !ends_on_itself(nodes, &done)
                && crossings_hold(
                    nodes,
                    &done,
                    crossed.iter().copied().chain(
                        support
                            .crossed
                            .iter()
                            .map(|&pulley| (pulley, path.nodes.len() - 1)),
                    ),
                )
            {
                *best = Some(done);
            }
        }
        // Passing `next`.
        for &turn in turn_options(nodes[next].kind) {
            if turn.is_none() {
                continue;
            }
            if let Some(support) = lookup(last, last_turn, next, turn) {
                path.nodes.push(next);
                path.turns.push(turn);
                path.covered += support.covered;
                path.missed += support.missed;
                path.on_mask += support.on_mask;
                let depth = crossed.len();
                let segment_index = path.nodes.len() - 2;
                crossed.extend(
                    support
                        .crossed
                        .iter()
                        .map(|&pulley| (pulley, segment_index)),
                );
                extend(nodes, path, crossed, lookup, best);
                crossed.truncate(depth);
                path.nodes.pop();
                path.turns.pop();
                path.covered -= support.covered;
                path.missed -= support.missed;
                path.on_mask -= support.on_mask;
            }
        }
    }
}

/// Whether a complete chain's crossings are a rope crossing itself: every pulley a segment passes
/// over is one the chain wraps, and that segment crosses another segment of the chain at an
/// angle. A rope lies over its own turn only where it crosses itself (a figure of eight); over
/// any other pulley it would have to pass through it, and a segment lying along another one
/// would be the same pixels counted twice.
fn crossings_hold(
    nodes: &[Node],
    path: &RopePath,
    crossed: impl Iterator<Item = (usize, usize)>,
) -> bool {
    let mut crossed = crossed.peekable();
    if crossed.peek().is_none() {
        // Most chains pass over nothing: no geometry to build.
        return true;
    }
    let segments = path.segments(nodes);
    crossed.all(|(pulley, crossing)| {
        if touches_behind(nodes, path, &segments, (pulley, crossing)) {
            return true;
        }
        let wrapped = path
            .nodes
            .iter()
            .zip(&path.turns)
            .any(|(&node, turn)| node == pulley && turn.is_some());
        wrapped
            && segments.get(crossing).is_some_and(|&own| {
                segments
                    .iter()
                    .enumerate()
                    .any(|(index, &other)| index != crossing && cross_at_an_angle(own, other))
            })
    })
}

/// Whether the pulley a stretch passes near is the chain's node just before the stretch's start
/// (or just after its end), lying behind that end: two pulleys that nearly touch, the rope
/// leaving the first and grazing the second on its way on (seed 6607's video 0). The stretch
/// then starts beside the first pulley's rim and heads away from it, which is no pass over it.
fn touches_behind(
    nodes: &[Node],
    path: &RopePath,
    segments: &[([f64; 2], [f64; 2])],
    (pulley, crossing): (usize, usize),
) -> bool {
    let (Some(&(start, end)), Some(node)) = (segments.get(crossing), nodes.get(pulley)) else {
        return false;
    };
    let heading = [end[0] - start[0], end[1] - start[1]];
    let away = |from: [f64; 2], sign: f64| {
        sign * ((from[0] - node.centre[0]) * heading[0] + (from[1] - node.centre[1]) * heading[1])
            >= 0.0
    };
    let before = crossing
        .checked_sub(1)
        .and_then(|index| path.nodes.get(index))
        == Some(&pulley);
    let after = path.nodes.get(crossing + 2) == Some(&pulley);
    (before && away(start, 1.0)) || (after && away(end, -1.0))
}

/// Distance from a stretch of a rope within which a point lies on it, units: far less than the
/// gap between the two strands hanging from one pulley (twice its wrap radius, 3.2 or more), and
/// wider than the error of positions read from pixels (a few tenths).
const ON_STRETCH: f64 = 0.5;

/// Whether an end of a complete chain lies on one of the chain's own stretches (other than the
/// one that ends there). A rope's end is where its pixels end; a candidate end read on the rope's
/// own strand (where its mask breaks off) is the rope going on, and a chain ending there rides
/// on the rope's own pixels to it, which can outscore the true chain (seed 6607's video 29). The
/// ends are where the rope is tied: the start of the first stretch and the end of the last.
fn ends_on_itself(nodes: &[Node], path: &RopePath) -> bool {
    let segments = path.segments(nodes);
    let on_another = |point: [f64; 2], own: usize| {
        segments.iter().enumerate().any(|(index, &(start, end))| {
            index != own && distance_to_segment(point, start, end) < ON_STRETCH
        })
    };
    match (segments.first(), segments.last()) {
        (Some(&(first_end, _)), Some(&(_, last_end))) => {
            on_another(first_end, 0) || on_another(last_end, segments.len() - 1)
        }
        _ => false,
    }
}

/// Least sine of the angle at which two segments of one rope must cross to count as the rope
/// crossing itself (20 degrees): nearly parallel segments that touch lie along each other.
const MIN_CROSSING_SINE: f64 = 0.342;

/// Whether two segments cross properly (each one's ends strictly on both sides of the other)
/// at an angle of at least [`MIN_CROSSING_SINE`].
fn cross_at_an_angle(a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])) -> bool {
    let cross = |o: [f64; 2], p: [f64; 2], q: [f64; 2]| {
        (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])
    };
    let sides_a = cross(a.0, a.1, b.0) * cross(a.0, a.1, b.1);
    let sides_b = cross(b.0, b.1, a.0) * cross(b.0, b.1, a.1);
    let (length_a, length_b) = (distance(a.0, a.1), distance(b.0, b.1));
    let direction_a = [a.1[0] - a.0[0], a.1[1] - a.0[1]];
    let direction_b = [b.1[0] - b.0[0], b.1[1] - b.0[1]];
    let sine = (direction_a[0] * direction_b[1] - direction_a[1] * direction_b[0]).abs()
        / (length_a * length_b);
    sides_a < 0.0 && sides_b < 0.0 && sine >= MIN_CROSSING_SINE
}

fn better(candidate: &RopePath, best: Option<&RopePath>) -> bool {
    let Some(best) = best else {
        return true;
    };
    let key = |p: &RopePath| {
        (
            std::cmp::Reverse(p.on_mask),
            std::cmp::Reverse(p.covered),
            p.missed,
            p.nodes.len(),
            p.nodes.clone(),
        )
    };
    key(candidate) < key(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pulley(x: f64, y: f64) -> Node {
        Node {
            kind: NodeKind::StaticPulley { solid: false },
            centre: [x, y],
        }
    }

    fn node(kind: NodeKind, x: f64, y: f64) -> Node {
        Node {
            kind,
            centre: [x, y],
        }
    }

    #[test]
    fn tangents_touch_both_circles_at_right_angles() {
        let a = pulley(0.0, 0.0);
        let b = node(NodeKind::MovablePulley { solid: true }, 5.0, -6.0);
        for turn_a in [Turn::CounterClockwise, Turn::Clockwise] {
            for turn_b in [Turn::CounterClockwise, Turn::Clockwise] {
                let (start, end) = segment(&a, Some(turn_a), &b, Some(turn_b)).unwrap();
                let radius_a = world::wrap_radius(false);
                let radius_b = world::wrap_radius(true);
                assert!((distance(start, a.centre) - radius_a).abs() < 1e-9);
                assert!((distance(end, b.centre) - radius_b).abs() < 1e-9);
                let direction = [end[0] - start[0], end[1] - start[1]];
                let radial = [start[0] - a.centre[0], start[1] - a.centre[1]];
                assert!((direction[0] * radial[0] + direction[1] * radial[1]).abs() < 1e-9);
                // The centre lies on the travel's left for a counter-clockwise turn.
                let cross = |centre: [f64; 2], at: [f64; 2]| {
                    direction[0] * (centre[1] - at[1]) - direction[1] * (centre[0] - at[0])
                };
                assert_eq!(
                    cross(a.centre, start) > 0.0,
                    turn_a == Turn::CounterClockwise
                );
                assert_eq!(cross(b.centre, end) > 0.0, turn_b == Turn::CounterClockwise);
            }
        }
    }

    #[test]
    fn a_load_hanging_off_a_pulley_hangs_from_its_rim() {
        // Travelling up from a load on the left of a pulley and wrapping it clockwise: the rope
        // runs vertically up to the pulley's leftmost point.
        let r = world::wrap_radius(false);
        let load = node(NodeKind::Load, -r, -6.0);
        let (start, end) = segment(&load, None, &pulley(0.0, 0.0), Some(Turn::Clockwise)).unwrap();
        assert!(
            (start[0] + r).abs() < 1e-9
                && (start[1] + 6.0 - world::LOAD_ATTACH_HEIGHT).abs() < 1e-9
        );
        assert!((end[0] + r).abs() < 1e-9 && end[1].abs() < 1e-9);
    }

    /// A pulley with a load on each side, an anchor elsewhere and a second pulley: the rope's
    /// pixels are drawn from its true path, and exactly that path comes back.
    #[test]
    fn the_drawn_chain_is_read_back_with_its_turns() {
        let r = world::wrap_radius(false);
        let nodes = vec![
            node(NodeKind::Load, -r, -6.0),
            pulley(0.0, 0.0),
            pulley(8.0, 0.0),
            node(NodeKind::Load, 8.0 + r, -7.0),
            node(NodeKind::Anchor, 4.0, 9.0),
        ];
        let truth = RopePath::unscored(
            vec![0, 1, 2, 3],
            vec![None, Some(Turn::Clockwise), Some(Turn::Clockwise), None],
        );
        let drawn = truth.polyline(&nodes, 0.05);
        let mut covers = |rope: usize, point: [f64; 2]| {
            Some(
                if rope == 0 && drawn.iter().any(|p| distance(*p, point) < 0.3) {
                    Sample::OnMask
                } else {
                    Sample::Missed
                },
            )
        };
        let read = read_ropes(&nodes, &[true, true], &mut covers);
        let path = read[0].as_ref().unwrap();
        assert_eq!(path.nodes, truth.nodes);
        assert_eq!(path.turns, truth.turns);
        assert!(path.missed == 0 && path.covered > 20, "{path:?}");
        assert!(read[1].is_none(), "a rope with no pixels has no path");
    }

    /// Reads one rope from the pixels `drawn` (see [`drawn_covers`]) and checks that `truth`'s
    /// chain comes back, with its turns.
    fn assert_reads_back(nodes: &[Node], drawn: &[[f64; 2]], truth: &RopePath) {
        let read = read_ropes(nodes, &[true], &mut drawn_covers(drawn));
        let path = read[0].as_ref().expect("the chain is read");
        assert_eq!(path.nodes, truth.nodes);
        assert_eq!(path.turns, truth.turns);
    }

    /// The pixels of a drawn rope, seen within 0.3 units of its centre line.
    fn drawn_covers(drawn: &[[f64; 2]]) -> impl FnMut(usize, [f64; 2]) -> Option<Sample> + '_ {
        move |_rope, point| {
            Some(if drawn.iter().any(|p| distance(*p, point) < 0.3) {
                Sample::OnMask
            } else {
                Sample::Missed
            })
        }
    }

    /// Seed 9473's video 9, in units from its first frame: a rope from a cube over a pulley,
    /// down across a second pulley to a third, round it and back over the second, which it wraps
    /// down to a cube. The stretch down lies over the second pulley's disc, which the rope wraps
    /// itself further on.
    fn figure_of_eight() -> (Vec<Node>, RopePath) {
        let solid = NodeKind::StaticPulley { solid: true };
        let nodes = vec![
            node(NodeKind::Load, -1.6, -4.8),
            node(solid, 0.0, 0.0),
            node(solid, -3.2, -11.1),
            node(solid, 0.3, -11.1),
            node(NodeKind::Load, -5.0, -16.5),
        ];
        let path = RopePath::unscored(
            vec![0, 1, 3, 2, 4],
            vec![
                None,
                Some(Turn::Clockwise),
                Some(Turn::CounterClockwise),
                Some(Turn::CounterClockwise),
                None,
            ],
        );
        (nodes, path)
    }

    #[test]
    fn a_rope_crossing_over_its_own_pulley_is_read() {
        let (nodes, truth) = figure_of_eight();
        let segments = truth.segments(&nodes);
        let (start, end) = segments[1];
        assert!(
            distance_to_segment(nodes[2].centre, start, end) < world::wrap_radius(true),
            "the stretch down passes over the second pulley"
        );
        let drawn = truth.polyline(&nodes, 0.05);
        assert_reads_back(&nodes, &drawn, &truth);
    }

    /// The pulleys each segment of `path` passes over, as the search records them: (pulley,
    /// segment index).
    fn crossings_of(nodes: &[Node], path: &RopePath) -> Vec<(usize, usize)> {
        path.segments(nodes)
            .into_iter()
            .enumerate()
            .flat_map(|(index, geometry)| {
                let ends = [path.nodes[index], path.nodes[index + 1]];
                passed_pulleys(nodes, ends, geometry)
                    .into_iter()
                    .map(move |pulley| (pulley, index))
            })
            .collect()
    }

    /// Seed 9473's video 45, in units from its first frame: a rope from a cube over a pulley and
    /// down past a second pulley it wraps by a few degrees, to a cube, with a candidate fixed
    /// point beside it. The chain the pixels also allowed before this rule (the lower cube
    /// straight up past the second pulley to the first, back down to the second, on to the fixed
    /// point) runs along the same pixels twice: its stretch past the second pulley crosses no
    /// other stretch, so it is no crossing. Video 9's chain does cross itself.
    #[test]
    fn only_a_rope_that_crosses_itself_may_pass_over_its_own_pulley() {
        let hollow = NodeKind::StaticPulley { solid: false };
        let nodes = vec![
            node(NodeKind::Load, -27.87, 0.40),
            node(hollow, -26.12, 6.0),
            node(hollow, -26.16, 17.9),
            node(NodeKind::Load, -27.91, 12.48),
            node(NodeKind::Anchor, -28.32, 2.82),
        ];
        let along_itself = RopePath::unscored(
            vec![0, 2, 1, 4],
            vec![
                None,
                Some(Turn::Clockwise),
                Some(Turn::CounterClockwise),
                None,
            ],
        );
        let crossings = crossings_of(&nodes, &along_itself);
        assert_eq!(
            crossings,
            vec![(1, 0)],
            "it passes over its own second pulley"
        );
        assert!(!crossings_hold(
            &nodes,
            &along_itself,
            crossings.into_iter()
        ));

        let (nodes, figure_of_eight) = figure_of_eight();
        let crossings = crossings_of(&nodes, &figure_of_eight);
        assert!(crossings.contains(&(2, 1)), "{crossings:?}");
        assert!(crossings_hold(
            &nodes,
            &figure_of_eight,
            crossings.into_iter()
        ));
    }

    /// Seed 6607's video 29, in units from its first frame: a rope from a cube over a solid
    /// pulley and two hollow ones down to a cube, with a candidate fixed point read where the
    /// rope's mask breaks on its stretch between the first two pulleys. The chain that ends there
    /// instead of at the second cube rides back over the pulleys on the rope's own pixels.
    #[test]
    fn a_rope_does_not_end_on_its_own_stretch() {
        let solid = NodeKind::StaticPulley { solid: true };
        let nodes = vec![
            node(solid, -16.24, 11.89),
            pulley(-12.51, 20.04),
            node(NodeKind::Load, -18.23, 6.42),
            pulley(-8.89, 19.85),
            node(NodeKind::Load, -7.16, 14.78),
            node(NodeKind::Anchor, -16.88, 15.57),
        ];
        let clockwise = Some(Turn::Clockwise);
        let truth = RopePath::unscored(
            vec![2, 0, 1, 3, 4],
            vec![None, clockwise, clockwise, clockwise, None],
        );
        let back_to_the_break = RopePath::unscored(
            vec![2, 0, 1, 3, 5],
            vec![
                None,
                clockwise,
                clockwise,
                Some(Turn::CounterClockwise),
                None,
            ],
        );
        assert!(ends_on_itself(&nodes, &back_to_the_break));
        assert!(!ends_on_itself(&nodes, &truth));
        // The pixels cover both chains, as the rope's pixels and colour do in the video; the
        // chain back to the break has the more samples and would win.
        let mut drawn = truth.polyline(&nodes, 0.05);
        drawn.extend(back_to_the_break.polyline(&nodes, 0.05));
        assert_reads_back(&nodes, &drawn, &truth);
    }

    /// Seed 6607's video 4, in units from its first frame: a rope from a sphere up over a solid
    /// pulley, across to a hollow pulley above it and down its far side to a sphere, with a
    /// candidate fixed point read below that sphere, beside the rope's crossing stretch. The
    /// stretch on to it would run through the sphere.
    #[test]
    fn a_rope_does_not_run_through_a_load() {
        let solid = NodeKind::StaticPulley { solid: true };
        let nodes = vec![
            node(NodeKind::Load, -7.17, -5.58),
            node(solid, -5.16, -0.06),
            pulley(-5.15, 11.89),
            node(NodeKind::Load, -6.83, 6.42),
            node(NodeKind::Anchor, -5.96, 3.83),
        ];
        let truth = RopePath::unscored(
            vec![0, 1, 2, 3],
            vec![
                None,
                Some(Turn::Clockwise),
                Some(Turn::CounterClockwise),
                None,
            ],
        );
        let on_to_the_anchor = segment(&nodes[2], Some(Turn::CounterClockwise), &nodes[4], None)
            .expect("a tangent exists");
        let everywhere = &mut |_point: [f64; 2]| Some(Sample::OnMask);
        let ends = [(2, true), (4, false)];
        assert_eq!(
            segment_support(&nodes, ends, on_to_the_anchor, everywhere),
            None
        );
        let drawn = truth.polyline(&nodes, 0.05);
        assert_reads_back(&nodes, &drawn, &truth);
    }

    /// Seed 6607's video 0, in units from its first frame: a rope from a sphere over a solid
    /// pulley, off it past a hollow pulley that nearly touches it, down past a second hollow
    /// pulley to a cube. The stretch from the first hollow pulley down starts beside the solid
    /// pulley's rim, within the graze distance of it, heading away from it.
    #[test]
    fn a_rope_grazing_the_pulley_beside_the_one_it_left_is_read() {
        let solid = NodeKind::StaticPulley { solid: true };
        let nodes = vec![
            node(NodeKind::Load, -16.93, 6.44),
            node(NodeKind::Load, -12.92, -5.64),
            node(solid, -14.93, 11.98),
            pulley(-11.29, 11.79),
            pulley(-11.21, -0.03),
        ];
        let truth = RopePath::unscored(
            vec![0, 2, 3, 4, 1],
            vec![
                None,
                Some(Turn::Clockwise),
                Some(Turn::CounterClockwise),
                Some(Turn::CounterClockwise),
                None,
            ],
        );
        let crossings = crossings_of(&nodes, &truth);
        assert_eq!(
            crossings,
            vec![(2, 2)],
            "the stretch down grazes the solid pulley"
        );
        let drawn = truth.polyline(&nodes, 0.05);
        assert_reads_back(&nodes, &drawn, &truth);
        // The stretch past the second hollow pulley does head towards the first one's disc:
        // a pass over it, refused.
        let reversed = RopePath::unscored(vec![0, 2, 4, 3, 1], truth.turns.clone());
        let segments = reversed.segments(&nodes);
        assert!(!touches_behind(&nodes, &reversed, &segments, (2, 2)));
    }

    /// A rope drawn straight from one load to another through a pulley's disc is no rope: it
    /// would pass through a pulley it does not wrap.
    #[test]
    fn a_rope_never_passes_over_a_pulley_it_does_not_wrap() {
        let nodes = vec![
            node(NodeKind::Load, -6.0, 0.0),
            pulley(0.0, 0.5),
            node(NodeKind::Load, 6.0, 0.0),
        ];
        let straight = RopePath::unscored(vec![0, 2], vec![None, None]);
        let drawn = straight.polyline(&nodes, 0.05);
        let read = read_ropes(&nodes, &[true], &mut drawn_covers(&drawn));
        assert!(
            read[0].as_ref().is_none_or(|path| path.nodes != vec![0, 2]),
            "{read:?}"
        );
    }

    #[test]
    fn a_rope_is_read_where_its_mask_is_before_where_only_its_colour_is() {
        // A long rope over a pulley, and a short one from a movable pulley's hook to its load:
        // the short rope's colour also matches the long rope's pixels (light strands), so by
        // covered samples alone it would be read along the long one.
        let r = world::wrap_radius(false);
        let nodes = vec![
            node(NodeKind::Load, -r, -6.0),
            pulley(0.0, 0.0),
            node(NodeKind::Load, r, -6.0),
            node(NodeKind::MovablePulley { solid: true }, 9.0, 0.0),
            node(NodeKind::Load, 9.0, -4.0),
        ];
        let long = RopePath::unscored(vec![0, 1, 2], vec![None, Some(Turn::Clockwise), None]);
        let short = RopePath::unscored(vec![3, 4], vec![None, None]);
        let long_pixels = long.polyline(&nodes, 0.05);
        let short_pixels = short.polyline(&nodes, 0.05);
        let near =
            |pixels: &[[f64; 2]], point: [f64; 2]| pixels.iter().any(|p| distance(*p, point) < 0.3);
        let mut covers = |_rope: usize, point: [f64; 2]| {
            Some(if near(&short_pixels, point) {
                Sample::OnMask
            } else if near(&long_pixels, point) {
                Sample::OnColour
            } else {
                Sample::Missed
            })
        };
        let read = read_ropes(&nodes, &[true], &mut covers);
        let read = read[0].as_ref().unwrap();
        assert_eq!(read.nodes, vec![3, 4], "{read:?}");
        assert!(read.on_mask >= 3, "{read:?}");
    }

    #[test]
    fn arcs_wrap_the_pulley_the_way_the_rope_turns() {
        let r = world::wrap_radius(false);
        let nodes = vec![
            node(NodeKind::Load, -r, -6.0),
            pulley(0.0, 0.0),
            node(NodeKind::Load, r, -6.0),
        ];
        let over_the_top =
            RopePath::unscored(vec![0, 1, 2], vec![None, Some(Turn::Clockwise), None]);
        let points = over_the_top.polyline(&nodes, 0.1);
        let highest = points.iter().map(|p| p[1]).fold(f64::MIN, f64::max);
        assert!(
            (highest - r).abs() < 0.01,
            "the rope passes over the top: {highest}"
        );
        assert!(points.windows(2).all(|w| distance(w[0], w[1]) < 0.11));
    }
}
