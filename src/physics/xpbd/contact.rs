//! Contacts of the cloth solver, found and projected as XPBD position constraints: cloth
//! particles against the table, the boxes and each other, and boxes against the table and each
//! other.
//!
//! * **Particle contacts** are found anew in every iteration (a closest point on a box is a few
//!   operations) and carry Obi's friction: positional, dynamic only (the release's static
//!   friction is 0), removing at most `μ` times the penetration of the tangential motion since
//!   the substep began (Macklin et al., "Unified Particle Physics for Real-Time Applications",
//!   2014). A particle against a box moves the box too, through its generalised inverse mass:
//!   this is the two-way coupling.
//! * **Rigid contacts** are found once a substep (Müller et al. 2020): each box carries sample
//!   points (its corners and points along its edges); a sample inside another box or below the
//!   table is a contact with that box's nearest face's normal. Iterations re-measure the
//!   penetration between the two body-attached points and add friction per contact patch as a
//!   positional constraint held within the Coulomb cone; after the substep a velocity pass
//!   removes the approaching normal velocity (PhysX's default bounciness, 0).
//!
//! Sampling edges instead of clipping faces finds edge-on-edge contacts only to within the
//! sample spacing; the scene's boxes are a few metres large and sampled every quarter edge.

use std::collections::BTreeSet;

use super::rigid::BoxBody;
use super::sheet::Sheet;
use crate::physics::vector3::{self as v3, Vector};

/// Samples per box edge, besides its two corners.
const EDGE_SAMPLES: usize = 3;
/// Contacts are collected within this distance before they touch, metres, so that a contact
/// closing during the substep's iterations is in the list.
const DETECTION_MARGIN: f64 = 0.02;

/// The other side of a rigid contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Other {
    /// The table, at this world point.
    Table(Vector),
    /// A box, at this point of its own frame.
    Box(usize, Vector),
}

/// A contact of a box's sample point.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct RigidContact {
    /// The box whose sample it is.
    pub body: usize,
    /// The sample, in that box's frame.
    pub local: Vector,
    /// What it touches.
    pub other: Other,
    /// Unit normal in the world, from the other side towards the body.
    pub normal: Vector,
    /// Accumulated normal multiplier of this substep, kg m (its force is this over h²).
    pub normal_multiplier: f64,
}

/// The contacts of one box with one other side (the table or a box): a contact patch, whose
/// friction acts as one constraint at the patch's centre within the Coulomb cone of the patch's
/// summed normal multipliers. Per-sample friction would hold each sample to its own share of the
/// load, which lets a box on an incline creep (measured: 4 mm/s at 20° with μ = 0.6).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Patch {
    /// The box.
    pub body: usize,
    /// The other box, or `None` for the table.
    pub other: Option<usize>,
    /// Indices of its contacts.
    pub members: Vec<usize>,
    /// Accumulated static-friction multiplier of this substep, kg m.
    pub tangent_multiplier: f64,
}

/// A substep's rigid contacts and their patches.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct RigidContacts {
    /// Every sample contact.
    pub contacts: Vec<RigidContact>,
    /// The contacts grouped by pair.
    pub patches: Vec<Patch>,
}

impl RigidContacts {
    /// Adds a contact to its pair's patch.
    fn push(&mut self, contact: RigidContact) {
        let other = match contact.other {
            Other::Table(_) => None,
            Other::Box(index, _) => Some(index),
        };
        let index = self.contacts.len();
        match self
            .patches
            .iter_mut()
            .find(|patch| patch.body == contact.body && patch.other == other)
        {
            Some(patch) => patch.members.push(index),
            None => self.patches.push(Patch {
                body: contact.body,
                other,
                members: vec![index],
                tangent_multiplier: 0.0,
            }),
        }
        self.contacts.push(contact);
    }
}

/// The sample points of a box in its own frame: corners and points along each edge.
pub(super) fn box_samples(half_extents: Vector) -> Vec<Vector> {
    let mut samples = Vec::with_capacity(8 + 12 * EDGE_SAMPLES);
    let corner = |index: usize| -> Vector {
        std::array::from_fn(|axis| {
            if index & (1 << axis) == 0 {
                -half_extents[axis]
            } else {
                half_extents[axis]
            }
        })
    };
    for index in 0..8 {
        samples.push(corner(index));
    }
    for index in 0..8 {
        for axis in 0..3 {
            // Each edge once: from the corner with this axis' bit clear.
            if index & (1 << axis) != 0 {
                continue;
            }
            let (from, to) = (corner(index), corner(index | (1 << axis)));
            for step in 1..=EDGE_SAMPLES {
                let t = step as f64 / (EDGE_SAMPLES + 1) as f64;
                samples.push(v3::add(from, v3::scale(v3::sub(to, from), t)));
            }
        }
    }
    samples
}

/// The rigid contacts at the start of a substep: box samples below the table (`table_height`,
/// metres) and inside other boxes.
pub(super) fn find_rigid_contacts(
    boxes: &[BoxBody],
    samples: &[Vec<Vector>],
    table_height: f64,
) -> RigidContacts {
    let mut found = RigidContacts::default();
    for (body, (subject, points)) in boxes.iter().zip(samples).enumerate() {
        for &local in points {
            let world = subject.to_world(local);
            if world[1] - table_height < DETECTION_MARGIN {
                found.push(RigidContact {
                    body,
                    local,
                    other: Other::Table([world[0], table_height, world[2]]),
                    normal: [0.0, 1.0, 0.0],
                    normal_multiplier: 0.0,
                });
            }
            for (other, target) in boxes.iter().enumerate() {
                if other == body || !near(subject, target, DETECTION_MARGIN) {
                    continue;
                }
                if let Some((face_point, normal)) = face_contact(target, world) {
                    found.push(RigidContact {
                        body,
                        local,
                        other: Other::Box(other, face_point),
                        normal,
                        normal_multiplier: 0.0,
                    });
                }
            }
        }
    }
    found
}

/// The pairs of boxes (lower index first) within `tolerance` of each other: a sample point of
/// one lies inside the other box grown by `tolerance` along each of its axes. A geometric reading
/// of "in contact", unlike a contact's multiplier, which is positive only in the substeps where
/// the pair penetrates and so flickers for a box resting on another (measured at 50 substeps:
/// a resting pair active in 1 to 31 of the last 40 updates).
pub(super) fn box_pairs_within(
    boxes: &[BoxBody],
    samples: &[Vec<Vector>],
    tolerance: f64,
) -> BTreeSet<(usize, usize)> {
    let mut pairs = BTreeSet::new();
    for (body, (subject, points)) in boxes.iter().zip(samples).enumerate() {
        for (other, target) in boxes.iter().enumerate() {
            let pair = (body.min(other), body.max(other));
            if other == body || pairs.contains(&pair) {
                continue;
            }
            if !near(subject, target, tolerance) {
                continue;
            }
            let within = points.iter().any(|&local| {
                let point = target.to_local(subject.to_world(local));
                (0..3).all(|axis| point[axis].abs() - target.half_extents[axis] <= tolerance)
            });
            if within {
                pairs.insert(pair);
            }
        }
    }
    pairs
}

/// Whether two boxes' bounding spheres, grown by `margin`, overlap.
fn near(a: &BoxBody, b: &BoxBody, margin: f64) -> bool {
    let reach = v3::norm(a.half_extents) + v3::norm(b.half_extents) + margin;
    v3::norm(v3::sub(a.position, b.position)) < reach
}

/// If `world` lies inside `target` or within the margin of one of its faces: the nearest face's
/// point under it (in `target`'s frame) and the face's outward normal (world).
fn face_contact(target: &BoxBody, world: Vector) -> Option<(Vector, Vector)> {
    let local = target.to_local(world);
    let outside: Vector = std::array::from_fn(|axis| local[axis].abs() - target.half_extents[axis]);
    if outside.iter().any(|&distance| distance > DETECTION_MARGIN) {
        return None;
    }
    // The face the point is closest to leaving through.
    let axis = (0..3)
        .max_by(|&a, &b| outside[a].total_cmp(&outside[b]))
        .unwrap_or(0);
    // Of the near-face points outside the box only those over the face itself count.
    if outside
        .iter()
        .enumerate()
        .any(|(other, &distance)| other != axis && distance > 0.0)
    {
        return None;
    }
    let sign = if local[axis] < 0.0 { -1.0 } else { 1.0 };
    let mut face_point = local;
    face_point[axis] = sign * target.half_extents[axis];
    let mut normal_local = [0.0; 3];
    normal_local[axis] = sign;
    Some((face_point, v3::apply(target.rotation(), normal_local)))
}

/// One Gauss–Seidel pass over the rigid contacts: every sample's normal constraint, then each
/// patch's static friction within `friction` times its summed normal multipliers.
pub(super) fn project_rigid(boxes: &mut [BoxBody], found: &mut RigidContacts, friction: f64) {
    for contact in &mut found.contacts {
        let (point, other_point) = contact_points(boxes, contact);
        let penetration = v3::dot(v3::sub(point, other_point), contact.normal);
        if penetration >= 0.0 {
            continue;
        }
        let other = other_box(contact);
        let change = -penetration / pair_weight(boxes, contact.body, other, point, contact.normal);
        contact.normal_multiplier += change;
        apply_pair(
            boxes,
            contact.body,
            other,
            point,
            v3::scale(contact.normal, change),
        );
    }
    for patch in &mut found.patches {
        let Some((local, normal, load)) = patch_centre(&found.contacts, patch) else {
            continue;
        };
        let body = &boxes[patch.body];
        let point = body.to_world(local);
        let moved = v3::sub(point, body.previous_world(local));
        let other_moved = match patch.other {
            None => [0.0; 3],
            Some(other) => {
                let other = &boxes[other];
                v3::sub(point, other.previous_world(other.to_local(point)))
            }
        };
        let slip = v3::sub(moved, other_moved);
        let tangential = v3::sub(slip, v3::scale(normal, v3::dot(slip, normal)));
        let length = v3::norm(tangential);
        if length < 1e-12 {
            continue;
        }
        let direction = v3::scale(tangential, 1.0 / length);
        let change = -length / pair_weight(boxes, patch.body, patch.other, point, direction);
        // Within the Coulomb cone the patch sticks; past it, the multiplier is held on the
        // cone and the rest of the slip is left to slide. The cone is measured against this
        // substep's load, which swings from substep to substep as the normal corrections
        // overshoot and settle; all or nothing here would let a box creep at 90% of μ.
        let bound = friction * load;
        let clamped = (patch.tangent_multiplier + change).clamp(-bound, bound);
        let applied = clamped - patch.tangent_multiplier;
        if applied != 0.0 {
            patch.tangent_multiplier = clamped;
            apply_pair(
                boxes,
                patch.body,
                patch.other,
                point,
                v3::scale(direction, applied),
            );
        }
    }
}

/// A patch's centre (the mean of its samples, in the body's frame), its mean normal and its
/// summed normal multiplier; `None` when none of its contacts pushed. The centre is the
/// geometric one, not the pushing samples': Gauss–Seidel lets the first samples of a resting box
/// carry the whole load, and friction at their mean would spin the box.
fn patch_centre(contacts: &[RigidContact], patch: &Patch) -> Option<(Vector, Vector, f64)> {
    let mut local = [0.0; 3];
    let mut normal = [0.0; 3];
    let mut load = 0.0;
    for contact in patch.members.iter().map(|&index| &contacts[index]) {
        local = v3::add(local, contact.local);
        normal = v3::add(normal, contact.normal);
        load += contact.normal_multiplier;
    }
    let length = v3::norm(normal);
    let count = patch.members.len() as f64;
    (load > 0.0 && length > 1e-12).then(|| {
        (
            v3::scale(local, 1.0 / count),
            v3::scale(normal, 1.0 / length),
            load,
        )
    })
}

/// After a substep: no bounce at the contacts that pushed (PhysX's default bounciness, 0).
/// Friction needs no velocity pass: the positional friction, held on the Coulomb cone when the
/// patch slides, is already the dynamic friction of the release's material (static and dynamic
/// coefficients equal); a second, velocity-level friction would count it twice (measured: a box
/// at 32° on μ = 0.6 crept at 0.4 mm/s instead of accelerating at 0.21 m/s²).
pub(super) fn rigid_velocities(boxes: &mut [BoxBody], found: &RigidContacts) {
    for contact in found.contacts.iter().filter(|c| c.normal_multiplier > 0.0) {
        let point = boxes[contact.body].to_world(contact.local);
        let other = other_box(contact);
        let velocity = relative_velocity(boxes, contact.body, other, point);
        let normal_speed = v3::dot(velocity, contact.normal);
        if normal_speed < 0.0 {
            let weight = pair_weight(boxes, contact.body, other, point, contact.normal);
            let impulse = v3::scale(contact.normal, -normal_speed / weight);
            apply_pair_velocity(boxes, contact.body, other, point, impulse);
        }
    }
}

/// The other box of a contact, if it is one.
fn other_box(contact: &RigidContact) -> Option<usize> {
    match contact.other {
        Other::Table(_) => None,
        Other::Box(index, _) => Some(index),
    }
}

/// The contact's two points in the world now.
fn contact_points(boxes: &[BoxBody], contact: &RigidContact) -> (Vector, Vector) {
    let point = boxes[contact.body].to_world(contact.local);
    let other_point = match contact.other {
        Other::Table(world) => world,
        Other::Box(other, local) => boxes[other].to_world(local),
    };
    (point, other_point)
}

/// Velocity of the body's material at `point` relative to the other box's (or the table's).
fn relative_velocity(
    boxes: &[BoxBody],
    body: usize,
    other: Option<usize>,
    point: Vector,
) -> Vector {
    let subject = &boxes[body];
    let velocity = subject.point_velocity(v3::sub(point, subject.position));
    match other {
        None => velocity,
        Some(other) => {
            let other = &boxes[other];
            v3::sub(
                velocity,
                other.point_velocity(v3::sub(point, other.position)),
            )
        }
    }
}

/// The summed generalised inverse masses of the two sides along `direction` at `point`.
fn pair_weight(
    boxes: &[BoxBody],
    body: usize,
    other: Option<usize>,
    point: Vector,
    direction: Vector,
) -> f64 {
    let subject = &boxes[body];
    let mut weight = subject.generalised_inverse_mass(v3::sub(point, subject.position), direction);
    if let Some(other) = other {
        let other = &boxes[other];
        weight += other.generalised_inverse_mass(v3::sub(point, other.position), direction);
    }
    weight
}

/// Applies the positional impulse at `point` to the body and its opposite to the other box.
fn apply_pair(
    boxes: &mut [BoxBody],
    body: usize,
    other: Option<usize>,
    point: Vector,
    impulse: Vector,
) {
    let subject = &mut boxes[body];
    subject.apply_correction(v3::sub(point, subject.position), impulse);
    if let Some(other) = other {
        let other = &mut boxes[other];
        other.apply_correction(v3::sub(point, other.position), v3::scale(impulse, -1.0));
    }
}

/// Applies the velocity impulse at `point` to the body and its opposite to the other box.
fn apply_pair_velocity(
    boxes: &mut [BoxBody],
    body: usize,
    other: Option<usize>,
    point: Vector,
    impulse: Vector,
) {
    let subject = &mut boxes[body];
    subject.apply_velocity_impulse(v3::sub(point, subject.position), impulse);
    if let Some(other) = other {
        let other = &mut boxes[other];
        other.apply_velocity_impulse(v3::sub(point, other.position), v3::scale(impulse, -1.0));
    }
}

/// Cloth particles against the table at `table_height`: one pass (the table does not move).
pub(super) fn project_particles_on_table(sheet: &mut Sheet, table_height: f64, friction: f64) {
    let radius = sheet.particle_radius();
    for k in 0..sheet.positions.len() {
        let inverse_mass = sheet.inverse_masses[k];
        if inverse_mass <= 0.0 {
            continue;
        }
        let depth = table_height + radius - sheet.positions[k][1];
        if depth <= 0.0 {
            continue;
        }
        sheet.positions[k][1] += depth;
        let moved = v3::sub(sheet.positions[k], sheet.previous[k]);
        let slide = [moved[0], 0.0, moved[2]];
        let length = v3::norm(slide);
        if length > 1e-12 {
            let keep = 1.0 - (friction * depth / length).min(1.0);
            sheet.positions[k][0] = sheet.previous[k][0] + moved[0] * keep;
            sheet.positions[k][2] = sheet.previous[k][2] + moved[2] * keep;
        }
    }
}

/// Cloth particles against the boxes, both ways: one pass. Marks in `touched[box]` the boxes a
/// particle pressed on.
pub(super) fn project_particles_on_boxes(
    sheet: &mut Sheet,
    boxes: &mut [BoxBody],
    friction: f64,
    touched: &mut [bool],
) {
    let radius = sheet.particle_radius();
    for (index, target) in boxes.iter_mut().enumerate() {
        let reach = v3::norm(target.half_extents) + radius;
        for k in 0..sheet.positions.len() {
            let position = sheet.positions[k];
            if v3::norm(v3::sub(position, target.position)) > reach {
                continue;
            }
            let Some((surface_local, normal, distance)) = closest_surface(target, position) else {
                continue;
            };
            let depth = radius - distance;
            if depth <= 0.0 {
                continue;
            }
            touched[index] = true;
            let inverse_mass = sheet.inverse_masses[k];
            let surface = target.to_world(surface_local);
            let arm = v3::sub(surface, target.position);
            let weight = inverse_mass + target.generalised_inverse_mass(arm, normal);
            let change = depth / weight;
            sheet.positions[k] =
                v3::add(sheet.positions[k], v3::scale(normal, inverse_mass * change));
            target.apply_correction(arm, v3::scale(normal, -change));

            // Friction: the tangential motion of the particle relative to the box's surface
            // point since the substep began, reduced by at most μ · depth.
            let surface = target.to_world(surface_local);
            let surface_moved = v3::sub(surface, target.previous_world(surface_local));
            let slip = v3::sub(
                v3::sub(sheet.positions[k], sheet.previous[k]),
                surface_moved,
            );
            let tangential = v3::sub(slip, v3::scale(normal, v3::dot(slip, normal)));
            let length = v3::norm(tangential);
            if length < 1e-12 {
                continue;
            }
            let direction = v3::scale(tangential, 1.0 / length);
            let arm = v3::sub(surface, target.position);
            let weight = inverse_mass + target.generalised_inverse_mass(arm, direction);
            let change = (friction * depth).min(length) / weight;
            sheet.positions[k] = v3::sub(
                sheet.positions[k],
                v3::scale(direction, inverse_mass * change),
            );
            target.apply_correction(arm, v3::scale(direction, change));
        }
    }
}

/// The point of `target`'s surface nearest to `world` (in the box's frame), the outward unit
/// normal there (world) and the signed distance (negative inside).
fn closest_surface(target: &BoxBody, world: Vector) -> Option<(Vector, Vector, f64)> {
    let local = target.to_local(world);
    let half = target.half_extents;
    let clamped: Vector = std::array::from_fn(|axis| local[axis].clamp(-half[axis], half[axis]));
    let outside = v3::sub(local, clamped);
    let distance = v3::norm(outside);
    if distance > 1e-12 {
        let normal = v3::apply(target.rotation(), v3::scale(outside, 1.0 / distance));
        return Some((clamped, normal, distance));
    }
    // Inside: leave through the nearest face.
    let axis = (0..3)
        .min_by(|&a, &b| (half[a] - local[a].abs()).total_cmp(&(half[b] - local[b].abs())))?;
    let sign = if local[axis] < 0.0 { -1.0 } else { 1.0 };
    let mut surface = local;
    surface[axis] = sign * half[axis];
    let mut normal = [0.0; 3];
    normal[axis] = sign;
    Some((
        surface,
        v3::apply(target.rotation(), normal),
        -(half[axis] - local[axis].abs()),
    ))
}

/// Pairs of a sheet's particles closer than `reach` (metres), not grid neighbours, in index
/// order. Particles are binned into cubic cells `reach` wide and sorted by cell; each occupied
/// cell finds its 27 neighbour cells by binary search over the occupied ones (no hashing: this
/// runs often, and a hash map took three quarters of a scene's run time).
pub(super) fn find_self_contacts(sheet: &Sheet, reach: f64) -> Vec<(usize, usize)> {
    #[expect(
        clippy::cast_possible_truncation,
        reason = "finite positions over a positive reach are far inside i64"
    )]
    let cell_of = |p: Vector| p.map(|v| (v / reach).floor() as i64);
    let mut sorted: Vec<([i64; 3], usize)> = sheet
        .positions
        .iter()
        .enumerate()
        .map(|(k, &position)| (cell_of(position), k))
        .collect();
    sorted.sort_unstable();
    // Occupied cells with the start of their run in `sorted`.
    let mut cells: Vec<([i64; 3], usize)> = Vec::new();
    for (index, (cell, _)) in sorted.iter().enumerate() {
        if cells.last().is_none_or(|(last, _)| last != cell) {
            cells.push((*cell, index));
        }
    }
    let members = |slot: usize| {
        let from = cells[slot].1;
        let to = cells.get(slot + 1).map_or(sorted.len(), |next| next.1);
        &sorted[from..to]
    };
    let mut pairs = Vec::new();
    for (slot, &([x, y, z], _)) in cells.iter().enumerate() {
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let cell = [x + dx, y + dy, z + dz];
                    let Ok(other) = cells.binary_search_by(|(key, _)| key.cmp(&cell)) else {
                        continue;
                    };
                    for &(_, a) in members(slot) {
                        for &(_, b) in members(other) {
                            if b <= a || sheet.are_neighbours(a, b) {
                                continue;
                            }
                            let gap = v3::norm(v3::sub(sheet.positions[b], sheet.positions[a]));
                            if gap < reach {
                                pairs.push((a, b));
                            }
                        }
                    }
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// One pass over the self-contact pairs: particles closer than two radii are pushed apart.
pub(super) fn project_self_contacts(sheet: &mut Sheet, pairs: &[(usize, usize)]) {
    let contact = 2.0 * sheet.particle_radius();
    for &(a, b) in pairs {
        let (wa, wb) = (sheet.inverse_masses[a], sheet.inverse_masses[b]);
        if wa + wb <= 0.0 {
            continue;
        }
        let between = v3::sub(sheet.positions[a], sheet.positions[b]);
        let distance = v3::norm(between);
        if distance >= contact || distance < 1e-12 {
            continue;
        }
        let direction = v3::scale(between, 1.0 / distance);
        let change = (contact - distance) / (wa + wb);
        sheet.positions[a] = v3::add(sheet.positions[a], v3::scale(direction, wa * change));
        sheet.positions[b] = v3::sub(sheet.positions[b], v3::scale(direction, wb * change));
    }
}
