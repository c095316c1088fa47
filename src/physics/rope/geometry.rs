//! Rope geometry at given body heights: where path points are (with drives), the rim tangent
//! contacts of every segment, wrap angles and arcs, rope lengths and their gradients over the
//! body heights, and the rope's centre line as a polyline.

use super::dynamics::numeric_gradient;
use super::mechanism::{Mechanism, State};
use super::network::{DrivenPoint, Mount, Point, SimulationError};

impl Mechanism {
    /// The rope's centre line in `state` as a polyline (m), from its first end to its last: the
    /// straight segments between rim tangent points and the arcs round the pulleys, sampled so
    /// that no arc step is longer than `arc_step` metres. Ends are the path's end points.
    pub fn rope_polyline(&self, rope: usize, state: &State, arc_step: f64) -> Vec<[f64; 2]> {
        self.now.set(state.time);
        let Some(path) = self.network.ropes.get(rope).map(|r| &r.path) else {
            return Vec::new();
        };
        let contacts = self.contacts(rope, &state.y);
        let mut points = Vec::new();
        for (segment, (from, to)) in contacts.iter().enumerate() {
            if segment == 0 {
                points.push(*from);
            } else {
                // The arc round the pulley between the previous segment's end and this start.
                let position = segment;
                let turn = self.turns[rope][position];
                if let (Point::Pulley(index), true) = (path[position], turn != 0.0) {
                    let centre = self.point_position(path[position], &state.y);
                    let radius = self.network.pulleys[index].radius;
                    let arrive = contacts[position - 1].1;
                    let from_angle = (arrive[1] - centre[1]).atan2(arrive[0] - centre[0]);
                    let sweep = self.wrap_angle(rope, position, &contacts, &state.y);
                    let step = arc_step.max(1e-3);
                    #[expect(
                        clippy::cast_possible_truncation,
                        clippy::cast_sign_loss,
                        reason = "a small positive count: an arc of at most 2π·R over a positive step"
                    )]
                    let count = ((sweep * radius / step).ceil() as usize).max(1);
                    for k in 1..count {
                        let angle = from_angle + turn * sweep * k as f64 / count as f64;
                        points.push([
                            centre[0] + radius * angle.cos(),
                            centre[1] + radius * angle.sin(),
                        ]);
                    }
                }
                points.push(*from);
            }
            points.push(*to);
        }
        points.dedup_by(|a, b| (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12);
        points
    }

    pub(super) fn point_position(&self, point: Point, y: &[f64]) -> [f64; 2] {
        match point {
            Point::Fixed(p) => self.driven(p, |target| target == DrivenPoint::Fixed(p)),
            Point::Body(index) => [self.network.bodies[index].position[0], y[index]],
            Point::Pulley(index) => match self.network.pulleys[index].mount {
                Mount::Fixed(p) => self.driven(p, |target| target == DrivenPoint::Pulley(index)),
                Mount::Body(body) => [self.network.bodies[body].position[0], y[body]],
            },
        }
    }

    /// `at`, moved by the drive whose target matches, at the current time.
    fn driven(&self, at: [f64; 2], matches: impl Fn(DrivenPoint) -> bool) -> [f64; 2] {
        let now = self.now.get();
        let lift: f64 = self
            .network
            .drives
            .iter()
            .filter(|drive| matches(drive.point))
            .map(|drive| drive.displacement(now))
            .sum();
        [at[0], at[1] + lift]
    }

    /// The contact points of every segment of `rope` at heights `y`.
    pub(super) fn contacts(&self, rope: usize, y: &[f64]) -> Vec<([f64; 2], [f64; 2])> {
        (0..self.network.ropes[rope].path.len() - 1)
            .map(|segment| self.segment_contacts(rope, segment, y))
            .collect()
    }

    /// Where segment `segment` of `rope` leaves its first end and meets its second: at a
    /// pulley the rope is tangent to the rim, on the side its turn puts it (a counter-clockwise
    /// turn keeps the pulley on the path's left, so the rope runs on its right).
    ///
    /// Closed form: with signed offsets `s = −turn·R` (0 for points) along the line's left
    /// normal `n`, the contacts are `c + s·n`, and `n ⟂ (c_b − c_a + (s_b − s_a) n)` gives
    /// `n = α·D̂ + √(1−α²)·left(D̂)` with `α = (s_a − s_b)/|D|`.
    fn segment_contacts(&self, rope: usize, segment: usize, y: &[f64]) -> ([f64; 2], [f64; 2]) {
        let path = &self.network.ropes[rope].path;
        let turns = &self.turns[rope];
        let offset = |position: usize| match path[position] {
            Point::Pulley(index) => -turns[position] * self.network.pulleys[index].radius,
            _ => 0.0,
        };
        let a = self.point_position(path[segment], y);
        let b = self.point_position(path[segment + 1], y);
        let (sa, sb) = (offset(segment), offset(segment + 1));
        let d = [b[0] - a[0], b[1] - a[1]];
        let distance = d[0].hypot(d[1]);
        if distance <= 0.0 || (sa == 0.0 && sb == 0.0) {
            return (a, b);
        }
        let unit = [d[0] / distance, d[1] / distance];
        let left = [-unit[1], unit[0]];
        let alpha = ((sa - sb) / distance).clamp(-1.0, 1.0);
        let beta = (1.0 - alpha * alpha).sqrt();
        let normal = [
            alpha * unit[0] + beta * left[0],
            alpha * unit[1] + beta * left[1],
        ];
        (
            [a[0] + sa * normal[0], a[1] + sa * normal[1]],
            [b[0] + sb * normal[0], b[1] + sb * normal[1]],
        )
    }

    /// Fails when a segment has no tangent: an end on or inside the pulley it wraps, or two
    /// pulleys too close for the rope to pass between them (opposite turns: the rope crosses
    /// between the rims) or round them (same turn).
    pub(super) fn check_tangents(&self, rope: usize, y: &[f64]) -> Result<(), SimulationError> {
        let path = &self.network.ropes[rope].path;
        let turns = &self.turns[rope];
        let wrapped = |position: usize| match path[position] {
            Point::Pulley(index) if turns[position] != 0.0 => {
                self.network.pulleys[index].radius * turns[position]
            }
            _ => 0.0,
        };
        for segment in 0..path.len() - 1 {
            let a = self.point_position(path[segment], y);
            let b = self.point_position(path[segment + 1], y);
            let distance = (a[0] - b[0]).hypot(a[1] - b[1]);
            // Signed radii: a tangent exists when the centres are further apart than the
            // difference of the signed radii (their sum for opposite turns).
            let needed = (wrapped(segment) - wrapped(segment + 1)).abs();
            if distance <= needed + 1e-9 {
                return Err(SimulationError::DegenerateSegment {
                    rope: self.network.ropes[rope].name.clone(),
                    segment,
                });
            }
        }
        Ok(())
    }

    /// The angle (rad, in `[0, 2π)`) from where the rope arrives at path point `position` to
    /// where it leaves, in the turn's direction, as the geometry gives it; 0 for ends and
    /// straight passes.
    pub(super) fn raw_wrap(
        &self,
        rope: usize,
        position: usize,
        contacts: &[([f64; 2], [f64; 2])],
        y: &[f64],
    ) -> f64 {
        let path = &self.network.ropes[rope].path;
        let turn = self.turns[rope][position];
        if !matches!(path[position], Point::Pulley(_))
            || turn == 0.0
            || position == 0
            || position + 1 >= path.len()
        {
            return 0.0;
        }
        let centre = self.point_position(path[position], y);
        let arrive = contacts[position - 1].1;
        let leave = contacts[position].0;
        let from = (arrive[1] - centre[1]).atan2(arrive[0] - centre[0]);
        let to = (leave[1] - centre[1]).atan2(leave[0] - centre[0]);
        (turn * (to - from)).rem_euclid(std::f64::consts::TAU)
    }

    /// The wrap angle round path point `position` (rad): the geometric angle read on the branch
    /// nearest the start's wrap, so it changes continuously as bodies move (a rope wrapped
    /// 300° stays 300°, a straight pass stays near 0 instead of jumping to a full turn), and
    /// never negative: a rope bending the other way at a pass has left the pulley.
    fn wrap_angle(
        &self,
        rope: usize,
        position: usize,
        contacts: &[([f64; 2], [f64; 2])],
        y: &[f64],
    ) -> f64 {
        let raw = self.raw_wrap(rope, position, contacts, y);
        let reference = self
            .wraps
            .get(rope)
            .and_then(|w| w.get(position))
            .copied()
            .unwrap_or(raw);
        let turns = ((reference - raw) / std::f64::consts::TAU).round();
        (raw + std::f64::consts::TAU * turns).max(0.0)
    }

    /// The rope wrapped round path point `position` (m): radius × its wrap angle.
    fn arc(
        &self,
        rope: usize,
        position: usize,
        contacts: &[([f64; 2], [f64; 2])],
        y: &[f64],
    ) -> f64 {
        let Point::Pulley(index) = self.network.ropes[rope].path[position] else {
            return 0.0;
        };
        self.network.pulleys[index].radius * self.wrap_angle(rope, position, contacts, y)
    }

    /// How close the two ends of a segment may come (m): a pulley's radius, a body's clearance.
    pub(super) fn clearance(&self, point: Point) -> f64 {
        match point {
            Point::Pulley(index) => self.network.pulleys[index].radius,
            Point::Body(index) => self.network.bodies[index].floor_clearance.unwrap_or(0.0),
            Point::Fixed(_) => 0.0,
        }
    }

    /// Length of segment `segment` of `rope` at heights `y`, m.
    pub(super) fn segment_length(&self, rope: usize, segment: usize, y: &[f64]) -> f64 {
        let (a, b) = self.segment_contacts(rope, segment, y);
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    /// A rope's current length: straight segments plus the arcs round its pulleys, m.
    pub fn rope_length(&self, rope: usize, y: &[f64]) -> f64 {
        self.length_to(rope, self.network.ropes[rope].path.len() - 1, y)
    }

    /// The rope length from the rope's start to where it arrives at path point `position`, m.
    pub(super) fn length_to(&self, rope: usize, position: usize, y: &[f64]) -> f64 {
        let contacts = self.contacts(rope, y);
        let straight: f64 = contacts[..position]
            .iter()
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
            .sum();
        let arcs: f64 = (1..position).map(|p| self.arc(rope, p, &contacts, y)).sum();
        straight + arcs
    }

    /// The gradient over body heights of the rope length up to path point `position` (the
    /// rope flows back over that pulley at `gradient · v`).
    pub(super) fn flow_gradient(&self, rope: usize, position: usize, y: &[f64]) -> Vec<f64> {
        numeric_gradient(
            |heights| self.length_to(rope, position, heights),
            y,
            &self.rope_bodies[rope],
        )
    }

    /// The bodies whose heights move a rope's points (loads tied to it, movable pulleys on it).
    pub(super) fn bodies_of(&self, rope: usize) -> Vec<usize> {
        let mut bodies: Vec<usize> = self.network.ropes[rope]
            .path
            .iter()
            .filter_map(|point| match *point {
                Point::Body(index) => Some(index),
                Point::Pulley(index) => match self.network.pulleys[index].mount {
                    Mount::Body(body) => Some(body),
                    Mount::Fixed(_) => None,
                },
                Point::Fixed(_) => None,
            })
            .collect();
        bodies.sort_unstable();
        bodies.dedup();
        bodies
    }
}

/// How the path turns at `at` coming from `before` and going to `after`: +1 counter-clockwise,
/// −1 clockwise. A straight horizontal pass rests on the top (a rope under gravity), so flow to
/// +x turns it clockwise; a straight vertical pass does not touch the pulley (0).
pub(super) fn inferred_turn(before: [f64; 2], at: [f64; 2], after: [f64; 2]) -> f64 {
    let incoming = [at[0] - before[0], at[1] - before[1]];
    let outgoing = [after[0] - at[0], after[1] - at[1]];
    let cross = incoming[0] * outgoing[1] - incoming[1] * outgoing[0];
    if cross.abs() > 1e-12 {
        cross.signum()
    } else if (after[0] - before[0]).abs() > 1e-12 {
        -(after[0] - before[0]).signum()
    } else {
        0.0
    }
}
