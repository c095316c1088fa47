//! The XPBD solver against known answers: a hanging cloth's static stretch against the linear
//! lattice of its compliant edges (whatever the iteration count), a box on an incline that slides
//! only past `tan θ = μ` and tips only past `tan θ = b / h`, no cloth particle inside a box, a light
//! plate swept over by a dragged cloth and an immovable one not, stiff and extreme cases finite
//! and bounded, and a golden hash.

use super::*;
use crate::physics::linalg;
use crate::physics::vector3::{self as v3, NO_ROTATION};

fn properties(stretch_compliance: f64, max_bending: f64, friction: f64) -> SheetProperties {
    SheetProperties {
        stretch_compliance,
        max_bending,
        friction,
    }
}

/// A square cloth of `resolution`² particles and side `side` whose back-left corner is at
/// `corner`, lying flat.
fn flat_sheet(resolution: usize, side: f64, corner: Vector, material: SheetProperties) -> Sheet {
    Sheet::new(&SheetSpec {
        resolution,
        side,
        corner,
        mass: 0.1 * side * side,
        particle_radius: 0.4 * side / (resolution - 1) as f64,
        properties: material,
    })
}

fn settings() -> XpbdSettings {
    XpbdSettings::default()
}

/// Runs `updates` updates; panics with the solver's error (tests only).
fn run(world: &mut World, updates: usize) -> Vec<UpdateContacts> {
    (0..updates)
        .map(|_| world.step().expect("the solver stays finite"))
        .collect()
}

/// The angle between a box's local up axis and the world's, degrees.
fn tilt_degrees(body: &BoxBody) -> f64 {
    let up = v3::apply(body.rotation(), [0.0, 1.0, 0.0]);
    up[1].clamp(-1.0, 1.0).acos().to_degrees()
}

/// A cloth hanging from its gripped top row in the x–y plane, settled; returns the mean drop of
/// its bottom row below its rest position, metres.
fn hanging_stretch(compliance: f64, substeps: usize, iterations: usize) -> f64 {
    let n = 11;
    let mut sheet = flat_sheet(n, 1.0, [0.0; 3], properties(compliance, 10.0, 0.0));
    let spacing = sheet.spacing();
    for (k, position) in sheet.positions.iter_mut().enumerate() {
        let (column, row) = (k % n, k / n);
        *position = [
            column as f64 * spacing,
            (row as f64 - (n - 1) as f64) * spacing,
            0.0,
        ];
    }
    sheet.previous = sheet.positions.clone();
    sheet.grip_front_edge();
    let rest: Vec<Vector> = sheet.positions().to_vec();
    let mut world = World::new(XpbdSettings {
        substeps,
        iterations,
        damping: 20.0,
        self_collision: false,
        table_height: -100.0,
        ..settings()
    })
    .unwrap();
    world.add_sheet(sheet);
    run(&mut world, 150);
    let sheet = &world.sheets()[0];
    (0..n)
        .map(|k| rest[k][1] - sheet.positions()[k][1])
        .sum::<f64>()
        / n as f64
}

/// The same cloth's drop by linear elasticity of its edge lattice: springs of stiffness 1/α along
/// the rest edges, the top row fixed, each particle's weight as the load.
fn lattice_stretch(compliance: f64) -> f64 {
    let n = 11;
    let sheet = flat_sheet(n, 1.0, [0.0; 3], properties(compliance, 10.0, 0.0));
    let spacing = sheet.spacing();
    let rest = |k: usize| [(k % n) as f64 * spacing, (k / n) as f64 * spacing];
    // Unknowns: (x, y) displacements of the particles below the top row (rows 0..n−1).
    let free = n * (n - 1);
    let mut stiffness = linalg::Matrix::zeros(2 * free);
    for (a, b, _) in sheet.edges() {
        let (pa, pb) = (rest(a), rest(b));
        let length = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
        let e = [(pb[0] - pa[0]) / length, (pb[1] - pa[1]) / length];
        let k = 1.0 / compliance;
        for (p, sign_p) in [(a, 1.0), (b, -1.0)] {
            for (q, sign_q) in [(a, 1.0), (b, -1.0)] {
                if p >= free || q >= free {
                    continue;
                }
                for i in 0..2 {
                    for j in 0..2 {
                        stiffness.add(2 * p + i, 2 * q + j, sign_p * sign_q * k * e[i] * e[j]);
                    }
                }
            }
        }
    }
    let mut load = vec![0.0; 2 * free];
    for k in 0..free {
        load[2 * k + 1] = -9.81 * sheet.masses()[k];
    }
    let displacement = linalg::solve(&stiffness, &load).expect("the lattice is held");
    -(0..n).map(|k| displacement[2 * k + 1]).sum::<f64>() / n as f64
}

#[test]
fn a_hanging_cloth_stretches_by_its_compliance_whatever_the_iteration_count() {
    // A 1-metre cloth of 0.1 kg with compliance 0.004 m/N: 1.3 mm of stretch, where the linear
    // lattice is exact to well under 1%.
    let compliance = 0.004;
    let expected = lattice_stretch(compliance);
    assert!(expected > 0.001 && expected < 0.002, "lattice {expected}");
    // Converged substeps (8 or 32 iterations) give the compliance's stretch, whatever the
    // count: the multiplier accumulates over the iterations (XPBD).
    let eight = hanging_stretch(compliance, 40, 8);
    let many = hanging_stretch(compliance, 40, 32);
    assert!(
        (eight - many).abs() < 1e-6 * expected,
        "8: {eight} m, 32: {many} m"
    );
    assert!(
        (eight - expected).abs() < 0.01 * expected,
        "XPBD {eight} m against the lattice's {expected} m"
    );
    // One iteration a substep converges to the same stretch as substeps shrink ("small steps");
    // at 10 substeps it leaves this stiff lattice unconverged, stretching it more.
    let small_steps = hanging_stretch(compliance, 100, 1);
    assert!(
        (small_steps - expected).abs() < 0.02 * expected,
        "100 substeps of 1 iteration: {small_steps} m against {expected} m"
    );
    // Ten times the compliance, ten times the stretch (within the lattice's geometric error).
    let ratio = hanging_stretch(10.0 * compliance, 40, 8) / eight;
    assert!(
        (ratio - 10.0).abs() < 0.15,
        "ten times the compliance: {ratio} times the stretch"
    );
    // A stiff cloth (compliance 0) barely stretches at all.
    let stiff = hanging_stretch(0.0, 40, 8);
    assert!(stiff < 0.1 * expected, "compliance 0 stretched {stiff} m");
}
/// A box of half extents `half` standing on the table under gravity tilted by `degrees` along
/// +x (a table inclined by that angle), after `updates`: (its slide along x in metres, its tilt
/// in degrees).
fn on_incline(half: Vector, degrees: f64, updates: usize) -> (f64, f64) {
    let angle = degrees.to_radians();
    let mut world = World::new(XpbdSettings {
        gravity: [9.81 * angle.sin(), -9.81 * angle.cos(), 0.0],
        ..settings()
    })
    .unwrap();
    world
        .add_box(BoxBody::new(half, 3.0, [0.0, half[1], 0.0], NO_ROTATION))
        .unwrap();
    run(&mut world, updates);
    let body = &world.boxes()[0];
    // Sliding moves the bottom's centre; tipping turns the box about its edge.
    let bottom = body.to_world([0.0, -half[1], 0.0]);
    (bottom[0], tilt_degrees(body))
}

#[test]
fn a_box_slides_only_past_the_friction_angle_at_the_coulomb_acceleration() {
    // A flat box (it cannot tip); μ = 0.6 is an incline of 30.96°.
    let flat = [0.5, 0.1, 0.5];
    let (slide, tilt) = on_incline(flat, 30.0, 120);
    assert!(
        slide.abs() < 0.001 && tilt < 0.5,
        "30°: slid {slide} m, tilted {tilt}°"
    );
    let (slide, tilt) = on_incline(flat, 32.0, 120);
    let angle = 32.0_f64.to_radians();
    let expected = 0.5 * 9.81 * (angle.sin() - 0.6 * angle.cos()) * 2.0 * 2.0;
    assert!(
        (slide - expected).abs() < 0.05 * expected,
        "32°: slid {slide} m in 2 s, Coulomb friction gives {expected} m"
    );
    assert!(tilt < 0.5, "32°: the flat box tilted {tilt}°");
}
#[test]
fn a_tall_box_tips_only_past_its_tipping_angle() {
    // Half extents 0.1 × 0.5: tan θ = b / h = 0.2, θ = 11.31°; μ = 0.6 > 0.2, so it tips before
    // it slides.
    let tall = [0.1, 0.5, 0.1];
    let (slide, tilt) = on_incline(tall, 10.3, 150);
    assert!(
        tilt < 1.0 && slide.abs() < 0.01,
        "10.3°: tilted {tilt}°, slid {slide} m"
    );
    let (_, tilt) = on_incline(tall, 12.3, 150);
    assert!(tilt > 45.0, "12.3°: tilted only {tilt}°");
}

/// A cloth of `resolution`² particles gripped at its front edge, which is at `front_z` and
/// `height`, centred on x = 0 and lying back along −z, in a world with the given boxes.
fn dragged_world(
    resolution: usize,
    side: f64,
    height: f64,
    front_z: f64,
    material: SheetProperties,
    boxes: &[BoxBody],
) -> World {
    let mut world = World::new(settings()).unwrap();
    let corner = [-side / 2.0, height, front_z - side];
    let mut sheet = flat_sheet(resolution, side, corner, material);
    sheet.grip_front_edge();
    world.add_sheet(sheet);
    for body in boxes {
        world.add_box(body.clone()).unwrap();
    }
    world
}

/// A standing plate (1.2 wide, 1.8 high, 0.4 thick, as the release's) of `mass` kg at z = 0.
fn plate(mass: f64) -> BoxBody {
    BoxBody::new([0.6, 0.9, 0.2], mass, [0.0, 0.9, 0.0], NO_ROTATION)
}

/// Drags the cloth along +z at `speed` m/s for `pull_updates`, then lets it go and runs
/// `settle_updates` more; returns every update's contacts.
fn drag(
    world: &mut World,
    speed: f64,
    pull_updates: usize,
    settle_updates: usize,
) -> Vec<UpdateContacts> {
    let sheet = world.sheet_mut(0).unwrap();
    sheet.set_handle_velocity([0.0, 0.0, speed]);
    let mut log = run(world, pull_updates);
    world.sheet_mut(0).unwrap().release();
    log.extend(run(world, settle_updates));
    log
}

#[test]
fn a_dragged_cloth_knocks_over_a_light_plate_and_slides_over_an_immovable_one() {
    let material = properties(0.011, 0.035, 4.0);
    let mut light = dragged_world(21, 3.0, 2.2, -1.5, material, &[plate(2.0)]);
    let log = drag(&mut light, 3.0, 80, 60);
    assert!(log.iter().any(|c| c.sheet_boxes.contains(&(0, 0))));
    let tilt = tilt_degrees(&light.boxes()[0]);
    assert!(tilt > 45.0, "the 2-kg plate tilted only {tilt}°");

    let mut heavy = dragged_world(21, 3.0, 2.2, -1.5, material, &[plate(99999.0)]);
    let log = drag(&mut heavy, 3.0, 80, 60);
    assert!(log.iter().any(|c| c.sheet_boxes.contains(&(0, 0))));
    let body = &heavy.boxes()[0];
    let moved = v3::norm(v3::sub(body.position, [0.0, 0.9, 0.0]));
    assert!(
        tilt_degrees(body) < 0.5 && moved < 0.005,
        "the 99999-kg plate tilted {}° and moved {moved} m",
        tilt_degrees(body)
    );
}

/// The deepest a cloth particle is inside any box, as a share of its radius (0 when none is).
fn deepest_penetration(world: &World) -> f64 {
    let sheet = &world.sheets()[0];
    let radius = sheet.particle_radius();
    let mut deepest: f64 = 0.0;
    for body in world.boxes() {
        for &position in sheet.positions() {
            let local = body.to_local(position);
            let outside: Vec<f64> = (0..3)
                .map(|axis| local[axis].abs() - body.half_extents[axis])
                .collect();
            let clamped: Vector = std::array::from_fn(|axis| outside[axis].max(0.0));
            let distance = if outside.iter().all(|d| *d <= 0.0) {
                outside.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            } else {
                v3::norm(clamped)
            };
            deepest = deepest.max((radius - distance) / radius);
        }
    }
    deepest
}

#[test]
fn no_cloth_particle_ends_up_inside_a_box_and_no_box_sinks_into_the_table() {
    let material = properties(0.0, 0.013, 0.5);
    let boxes = [
        plate(2.0),
        BoxBody::new([0.25, 1.0, 0.25], 6.5, [0.0, 1.0, -1.0], NO_ROTATION),
    ];
    let mut world = dragged_world(21, 3.0, 2.4, -2.0, material, &boxes);
    world
        .sheet_mut(0)
        .unwrap()
        .set_handle_velocity([0.0, 0.0, 3.0]);
    let mut deepest: f64 = 0.0;
    let mut lowest = f64::INFINITY;
    for update in 0..160 {
        if update == 90 {
            world.sheet_mut(0).unwrap().release();
        }
        world.step().unwrap();
        deepest = deepest.max(deepest_penetration(&world));
        for body in world.boxes() {
            for corner in body.corners() {
                lowest = lowest.min(corner[1]);
            }
        }
    }
    // A particle may end a substep overlapping a box by part of its radius (it never enters).
    assert!(
        deepest < 1.0,
        "a particle reached {deepest} radii into a box"
    );
    assert!(lowest > -0.01, "a box corner sank to {lowest} m");
}

#[test]
fn stiff_and_extreme_cases_stay_finite_and_bounded() {
    let cases: [(&str, SheetProperties, f64, f64); 4] = [
        ("compliance 0", properties(0.0, 0.013, 4.0), 3.0, 2.0),
        ("a very soft cloth", properties(1.0, 0.035, 0.5), 3.0, 2.0),
        (
            "pulled at 10× speed",
            properties(0.011, 0.035, 4.0),
            30.0,
            2.0,
        ),
        (
            "a 99999-kg plate",
            properties(0.011, 0.013, 4.0),
            3.0,
            99999.0,
        ),
    ];
    for (name, material, speed, mass) in cases {
        let mut world = dragged_world(21, 3.0, 2.2, -1.5, material, &[plate(mass)]);
        // 4 metres of pull at `speed`: 80 updates at 3 m/s, 8 at 30.
        let pull = if speed > 10.0 { 8 } else { 80 };
        drag(&mut world, speed, pull, 60);
        let sheet = &world.sheets()[0];
        let furthest = sheet
            .positions()
            .iter()
            .map(|p| v3::norm(*p))
            .fold(0.0, f64::max);
        let fastest = sheet
            .velocities()
            .iter()
            .map(|v| v3::norm(*v))
            .fold(0.0, f64::max);
        // Released at the handle's speed, a particle flies on for the last second at most that
        // fast plus what gravity adds.
        let seconds = (pull + 60) as f64 / 60.0;
        assert!(
            furthest < 10.0 + speed * seconds,
            "{name}: a particle went {furthest} m away"
        );
        assert!(
            fastest < speed + 15.0,
            "{name}: a particle moves {fastest} m/s"
        );
        assert!(
            world.boxes()[0].position[1] > 0.0,
            "{name}: the plate fell through"
        );
    }
}

#[test]
fn a_thin_plate_stops_a_cloth_driven_at_it_even_at_ten_times_the_speed() {
    // An immovable wall 2 cm thick and 4 m tall: the cloth, held at 1.5 m, cannot pass above it.
    for speed in [3.0, 30.0] {
        let wall = BoxBody::new([2.0, 2.0, 0.01], 99999.0, [0.0, 2.0, 0.0], NO_ROTATION);
        let mut world = dragged_world(21, 2.0, 1.5, -0.3, properties(0.011, 0.035, 0.5), &[wall]);
        world
            .sheet_mut(0)
            .unwrap()
            .set_handle_velocity([0.0, 0.0, speed]);
        // The handle runs to just short of the wall (5 updates at 3 m/s; at 30 m/s it is let go
        // at once), then the cloth is flung against the wall at the handle's speed.
        let updates = if speed > 10.0 { 0 } else { 5 };
        run(&mut world, updates);
        world.sheet_mut(0).unwrap().release();
        run(&mut world, 60);
        let crossed = world.sheets()[0]
            .positions()
            .iter()
            .filter(|p| p[2] > 0.01)
            .count();
        assert_eq!(
            crossed, 0,
            "{crossed} particles passed the wall at {speed} m/s"
        );
    }
}

/// A cloth dropped onto a blade standing under the gap between two rows of its particles: the
/// mean height of those two rows over the blade, after 1 s, against the blade's top (0.5 m).
fn rows_over_a_blade(edges_against_triangles: bool) -> f64 {
    let mut world = World::new(XpbdSettings {
        box_edges: edges_against_triangles,
        ..settings()
    })
    .unwrap();
    // Rows at z = −0.5 + 0.1 k; the blade (1 cm thick, top at 0.5 m) under z = 0.05.
    let blade = BoxBody::new([0.3, 0.25, 0.005], 99999.0, [0.0, 0.25, 0.05], NO_ROTATION);
    world.add_box(blade).unwrap();
    world.add_sheet(flat_sheet(
        11,
        1.0,
        [-0.5, 0.6, -0.5],
        properties(0.0, 0.02, 0.5),
    ));
    run(&mut world, 60);
    let sheet = &world.sheets()[0];
    let over: Vec<f64> = (3..=7)
        .flat_map(|column| [5 * 11 + column, 6 * 11 + column])
        .map(|k| sheet.positions()[k][1])
        .collect();
    over.iter().sum::<f64>() / over.len() as f64
}

#[test]
fn a_box_edge_does_not_slip_between_the_cloths_particles() {
    // Particles alone: the 1-cm blade passes through the 2-cm gap between two rows' particle
    // spheres, and the rows sink on either side of it. Edges against triangles: the cloth rests
    // on the blade's top.
    let wedged = rows_over_a_blade(false);
    let resting = rows_over_a_blade(true);
    assert!(wedged < 0.45, "particles alone: rows at {wedged:.3} m");
    assert!(
        resting > 0.5,
        "edges against triangles: rows at {resting:.3} m"
    );
}

#[test]
fn settings_out_of_range_are_named() {
    let error = World::new(XpbdSettings {
        substeps: 0,
        ..settings()
    })
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "XPBD solver setting `substeps` is 0; expected 1 to 10000"
    );
    let mut world = World::new(settings()).unwrap();
    let error = world
        .add_box(BoxBody::new([0.1; 3], 0.0, [0.0; 3], NO_ROTATION))
        .unwrap_err();
    assert_eq!(
        error.to_string(),
        "box 0: mass 0 kg is not positive and finite"
    );
}

#[test]
fn a_dragged_cloth_scene_has_a_golden_hash() {
    let boxes = [
        plate(2.0),
        BoxBody::new([0.25, 1.0, 0.25], 6.5, [0.3, 1.0, -1.0], NO_ROTATION),
    ];
    let mut world = dragged_world(11, 3.0, 2.2, -1.5, properties(0.011, 0.035, 2.25), &boxes);
    drag(&mut world, 3.0, 60, 30);
    let mut hasher = blake3::Hasher::new();
    for position in world.sheets()[0].positions() {
        for value in position {
            hasher.update(&value.to_le_bytes());
        }
    }
    for body in world.boxes() {
        for value in body.position.iter().chain(&body.orientation) {
            hasher.update(&value.to_le_bytes());
        }
    }
    let hash = hasher.finalize().to_hex().to_string();
    assert_eq!(
        hash,
        "4e2be7f59c4e99c9bca3b0b1036252419dfb98e56684dafa456532fadb59af4b"
    );
}

#[test]
fn boxes_within_a_tolerance_touch_steadily_where_contacts_flicker() {
    // Side by side on the table, 5 mm and 30 mm apart: within 10 mm only the first pair.
    let mut world = World::new(settings()).unwrap();
    for x in [0.0, 1.005, 2.035] {
        world
            .add_box(BoxBody::new(
                [0.5, 0.5, 0.5],
                3.0,
                [x, 0.5, 0.0],
                NO_ROTATION,
            ))
            .unwrap();
    }
    assert_eq!(world.box_pairs_within(0.01), BTreeSet::from([(0, 1)]));
    assert!(world.box_pairs_within(0.001).is_empty());
    // A box resting on another at the fine reference's 50 substeps: it touches at every
    // update, though its contact's multiplier is positive only in the substeps it penetrates.
    let mut world = World::new(XpbdSettings {
        substeps: 50,
        iterations: 4,
        ..settings()
    })
    .unwrap();
    world
        .add_box(BoxBody::new(
            [0.5, 0.5, 0.5],
            99999.0,
            [0.0, 0.5, 0.0],
            NO_ROTATION,
        ))
        .unwrap();
    world
        .add_box(BoxBody::new(
            [0.3, 0.2, 0.3],
            2.0,
            [0.1, 1.2, 0.0],
            NO_ROTATION,
        ))
        .unwrap();
    run(&mut world, 60);
    for _ in 0..20 {
        world.step().unwrap();
        assert_eq!(world.box_pairs_within(0.01), BTreeSet::from([(0, 1)]));
    }
    let top = world.boxes()[1].position;
    assert!((top[1] - 1.2).abs() < 0.01, "{top:?}");
}
