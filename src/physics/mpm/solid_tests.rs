//! Tests of the MPM core's solids: elastoplastic discs and rigid bodies, against closed forms
//! (line-contact Hertz, rolling on an incline) and physical invariants.

use super::*;

/// A square grid of `nodes` a side and spacing `dx`, Taichi's walls.
fn grid(nodes: usize, dx: f64) -> GridSpec {
    GridSpec {
        origin: [0.0, 0.0],
        spacing: dx,
        nodes: [nodes, nodes],
        walls: Walls { low: 3, high: 3 },
    }
}

fn solid(youngs_modulus: f64, poisson_ratio: f64, yield_stress: f64) -> Material {
    Material::Elastoplastic(ElastoplasticMaterial {
        density: 1.0,
        youngs_modulus,
        poisson_ratio,
        yield_stress,
    })
}

const RIGID: Material = Material::Rigid(RigidMaterial {
    density: 1.0,
    friction: 0.3,
    rolling_resistance: 0.0,
    collider_friction: None,
});

/// Adds a disc of `material` (a body when the material is rigid); returns its particle count.
fn add_disc(
    solver: &mut Solver,
    material: usize,
    center: [f64; 2],
    radius: f64,
    velocity: [f64; 2],
) -> usize {
    let spacing = solver.grid().spacing * 0.5;
    let points = disc_lattice(center, radius, spacing);
    let volume = spacing * spacing;
    if let Material::Rigid(_) = solver.materials()[material] {
        solver
            .add_rigid_body(material, radius, &points, velocity, 0.0, volume)
            .expect("a valid body");
    } else {
        for &point in &points {
            solver
                .add_particle(material, point, velocity, volume)
                .expect("a particle inside the grid");
        }
    }
    points.len()
}

fn floor(height: f64, friction: f64) -> Collider {
    Collider {
        shape: Shape::HalfPlane {
            point: [0.0, height],
            normal: [0.0, 1.0],
        },
        boundary: Boundary::Separate { friction },
    }
}

/// Centre of mass and its velocity over the particles of `material`.
fn centre(solver: &Solver, material: usize) -> ([f64; 2], [f64; 2]) {
    let mut mass_sum = 0.0;
    let mut position = [0.0; 2];
    let mut velocity = [0.0; 2];
    for (state, which, mass) in solver.particles_by_id() {
        if which == material {
            mass_sum += mass;
            for axis in 0..2 {
                position[axis] += mass * state.position[axis];
                velocity[axis] += mass * state.velocity[axis];
            }
        }
    }
    (
        position.map(|p| p / mass_sum),
        velocity.map(|v| v / mass_sum),
    )
}

/// Kinetic plus elastic energy (plus gravitational, for gravity `g` along −y, from y = 0).
fn energy(solver: &Solver, g: f64) -> f64 {
    solver
        .particles_by_id()
        .iter()
        .map(|(state, material, mass)| {
            let speed_squared = state.velocity[0].powi(2) + state.velocity[1].powi(2);
            let volume = mass / solver.materials()[*material].density();
            0.5 * mass * speed_squared
                + volume * solver.materials()[*material].energy_density(&state.deformation)
                + mass * g * state.position[1]
        })
        .sum()
}

/// The disc's rebound off a rigid floor without gravity: (contact time, restitution, largest
/// rise of the energy from one millisecond to the next over the start's energy). Contact: the
/// time the floor pushes (the centre's velocity changes, which without gravity it does only
/// then).
fn rebound(youngs_modulus: f64, speed: f64) -> (f64, f64, f64) {
    let (dx, radius) = (0.05, 0.5);
    let settings = Settings {
        gravity: [0.0, 0.0],
        ..Settings::default()
    };
    let mut solver = Solver::new(
        grid(48, dx),
        vec![solid(youngs_modulus, 0.3, f64::INFINITY)],
        &[floor(0.4, 0.0)],
        settings,
    )
    .unwrap();
    add_disc(
        &mut solver,
        0,
        [1.2, 0.4 + radius + 0.1],
        radius,
        [0.0, -speed],
    );
    let start = energy(&solver, 0.0);
    let (mut contact_start, mut contact_end) = (None, None);
    let mut previous = start;
    let mut rise: f64 = 0.0;
    let mut last = centre(&solver, 0).1[1];
    let frame = 1e-3;
    for index in 1..=1500 {
        solver.advance(frame).unwrap();
        let velocity = centre(&solver, 0).1[1];
        let now = energy(&solver, 0.0);
        rise = rise.max(now - previous);
        previous = now;
        // Without gravity the centre's velocity changes only while the floor pushes.
        let pushed = (velocity - last).abs() > 1e-6 * speed;
        let time = f64::from(index) * frame;
        if pushed {
            contact_start.get_or_insert(time - frame);
            contact_end = Some(time);
        }
        last = velocity;
        if contact_end.is_some_and(|end| time > end + 0.05) {
            break;
        }
    }
    let contact = contact_end.unwrap() - contact_start.unwrap();
    (contact, last / speed, rise / start)
}

/// Contact time of a disc of radius `r`, density `ρ` and plane-strain modulus `E*` hitting a rigid
/// wall at `speed`, from the line-contact (2D Hertz) law: the centre approaches by
/// `δ = P/(πE*)·(ln(4πE*R/P) − 1)` under a force `P` per unit length (Johnson, Contact Mechanics
/// §5.6, with the contact half-width `a = √(4PR/(πE*))`), integrated as a mass on that spring.
fn line_contact_time(radius: f64, density: f64, plane_strain_modulus: f64, speed: f64) -> f64 {
    let mass = density * std::f64::consts::PI * radius * radius;
    let stiffness = std::f64::consts::PI * plane_strain_modulus;
    let approach = |force: f64| force / stiffness * ((4.0 * stiffness * radius / force).ln() - 1.0);
    // P(δ) by bisection on the increasing branch (P < 4πE*R/e²).
    let force_at = |delta: f64| {
        let (mut low, mut high) = (0.0, 4.0 * stiffness * radius / std::f64::consts::E.powi(2));
        for _ in 0..100 {
            let middle = 0.5 * (low + high);
            if approach(middle) < delta {
                low = middle;
            } else {
                high = middle;
            }
        }
        low
    };
    let (mut delta, mut velocity, mut time) = (0.0f64, speed, 0.0);
    let dt = 1e-7;
    while delta >= 0.0 {
        velocity -= dt * force_at(delta.max(0.0)) / mass;
        delta += dt * velocity;
        time += dt;
    }
    time
}

#[test]
fn an_elastic_disc_rebounds_in_the_line_contact_time_and_never_gains_energy() {
    // Measured (dx 0.05; dx 0.025 in brackets): E 200: 0.221 s (0.211) against the estimate
    // 0.185, E 800: 0.131 s (0.119) against 0.105; the ratio 1.69 (1.77) against 1.77. MPM's
    // contact also lasts while the disc crosses the cell or so in which the floor's nodes reach
    // its particles (about 0.04 s at 2 units/s), so it runs 12–26% long, less on finer grids.
    let speed = 2.0;
    let plane_strain = |e: f64| e / (1.0 - 0.3 * 0.3);
    let mut times = Vec::new();
    for youngs_modulus in [200.0, 800.0] {
        let (contact, restitution, rise) = rebound(youngs_modulus, speed);
        let estimate = line_contact_time(0.5, 1.0, plane_strain(youngs_modulus), speed);
        assert!(
            contact > estimate && contact < 1.3 * estimate,
            "E {youngs_modulus}: contact {contact} s, estimate {estimate} s"
        );
        // APIC keeps most of the energy; what it loses goes into the grid, never the other way.
        assert!(
            (0.65..1.0).contains(&restitution),
            "E {youngs_modulus}: restitution {restitution}"
        );
        // Kinetic plus elastic energy measured on the particles is not exactly monotone from one
        // millisecond to the next (largest rise measured: 4e-5 of the start).
        assert!(
            rise <= 1e-4,
            "E {youngs_modulus}: energy rose by {rise} of the start"
        );
        times.push((contact, estimate));
    }
    let (measured, expected) = (times[0].0 / times[1].0, times[0].1 / times[1].1);
    assert!(
        (measured / expected - 1.0).abs() < 0.1,
        "contact time ratio {measured} for 4× the stiffness, estimate {expected}"
    );
}

/// A disc of `material` dropped from `height` (its lowest point above the floor at y = 0.4) onto a
/// frictional floor; returns the solver after it lands and settles, and its particle count.
fn drop_disc(material: Material, height: f64, settle: f64) -> (Solver, usize) {
    let (dx, radius) = (0.05, 0.5);
    let mut solver = Solver::new(
        grid(100, dx),
        vec![material],
        &[floor(0.4, 0.5)],
        Settings::default(),
    )
    .unwrap();
    let count = add_disc(
        &mut solver,
        0,
        [2.5, 0.4 + radius + height],
        radius,
        [0.0; 2],
    );
    let fall = (2.0 * height / 9.8).sqrt();
    solver.advance(fall + settle).unwrap();
    (solver, count)
}

/// Width minus height of the particles' extent, over the diameter: 0 for a round disc.
fn flattening(solver: &Solver) -> f64 {
    let particles = solver.particles_by_id();
    let extent = |axis: usize| {
        let values = particles.iter().map(|(state, _, _)| state.position[axis]);
        values.clone().fold(f64::MIN, f64::max) - values.fold(f64::MAX, f64::min)
    };
    (extent(0) - extent(1)) / 1.0
}

#[test]
fn a_plastic_disc_flattens_more_the_higher_it_falls_and_an_elastic_one_recovers() {
    let plastic = solid(500.0, 0.3, 40.0);
    let flattenings: Vec<f64> = [0.25, 1.0, 2.5, 0.0]
        .iter()
        .map(|&height| flattening(&drop_disc(plastic, height, 0.6).0))
        .collect();
    let elastic = flattening(&drop_disc(solid(500.0, 0.3, f64::INFINITY), 2.5, 0.6).0);
    // Measured: resting 0.034 (its own weight), then 0.10, 0.38, 0.77 after drops of 0.25, 1 and
    // 2.5 units; the elastic disc from 2.5 units −0.11 (it is still ringing and bouncing).
    let [low, middle, high, resting] = flattenings[..] else {
        panic!("four drops");
    };
    assert!(
        resting < low && low < middle && middle < high,
        "flattening by drop height (0.25, 1, 2.5, 0): {flattenings:?}"
    );
    assert!(high > 0.5, "{flattenings:?}");
    assert!(
        elastic.abs() < 0.15,
        "the elastic disc keeps its shape: {elastic}"
    );
}

/// Distance a disc travels down a 30° incline with `friction` in `time` seconds from rest.
fn incline_travel(material: Material, friction: f64, time: f64) -> f64 {
    let (dx, radius) = (0.05, 0.5);
    let angle = 30f64.to_radians();
    let normal = [-angle.sin(), angle.cos()];
    let on_plane = [0.3, 0.4];
    let incline = Collider {
        shape: Shape::HalfPlane {
            point: on_plane,
            normal,
        },
        boundary: Boundary::Separate { friction },
    };
    let mut solver = Solver::new(
        grid(72, dx),
        vec![material],
        &[incline],
        Settings::default(),
    )
    .unwrap();
    // Touching the plane, 2.4 units up it.
    let along = [angle.cos(), angle.sin()];
    let start = [
        on_plane[0] + 2.4 * along[0] + radius * normal[0],
        on_plane[1] + 2.4 * along[1] + radius * normal[1],
    ];
    add_disc(&mut solver, 0, start, radius, [0.0; 2]);
    let before = centre(&solver, 0).0;
    solver.advance(time).unwrap();
    let after = centre(&solver, 0).0;
    -((after[0] - before[0]) * along[0] + (after[1] - before[1]) * along[1])
}

#[test]
fn discs_roll_down_an_incline_at_two_thirds_of_g_sin_theta() {
    let time = 0.6;
    let g_sin = 9.8 * 0.5;
    let rolling = 0.5 * (2.0 / 3.0) * g_sin * time * time;
    let sliding = 0.5 * g_sin * time * time;
    let rigid_rolls = incline_travel(RIGID, 0.5, time);
    let rigid_slides = incline_travel(RIGID, 0.0, time);
    let elastic_rolls = incline_travel(solid(2000.0, 0.3, f64::INFINITY), 0.5, time);
    let elastic_slides = incline_travel(solid(2000.0, 0.3, f64::INFINITY), 0.0, time);
    // Measured: rigid 0.605 rolling and 0.918 sliding (+2.9%, +4.0%: symplectic Euler's
    // first-order error at the substeps of up to 0.05 s a scene without waves takes); elastic
    // 0.542 (−7.9%: the contact patch also dissipates) and 0.8827 (+0.08%).
    let within = |measured: f64, expected: f64, tolerance: f64| {
        (measured / expected - 1.0).abs() < tolerance
    };
    assert!(
        within(rigid_rolls, rolling, 0.05),
        "rigid rolls {rigid_rolls}, {rolling}"
    );
    assert!(
        within(rigid_slides, sliding, 0.05),
        "rigid slides {rigid_slides}, {sliding}"
    );
    assert!(
        within(elastic_rolls, rolling, 0.1),
        "elastic rolls {elastic_rolls}, {rolling}"
    );
    assert!(
        within(elastic_slides, sliding, 0.02),
        "elastic slides {elastic_slides}, {sliding}"
    );
}

/// Every particle finite, slower than `max_speed`, and no deeper than `depth` below `floor_y`.
fn assert_sane(solver: &Solver, max_speed: f64, floor_y: f64, depth: f64, case: &str) {
    for (state, _, _) in solver.particles_by_id() {
        let speed = state.velocity[0].hypot(state.velocity[1]);
        assert!(
            speed.is_finite() && speed < max_speed,
            "{case}: speed {speed}"
        );
        assert!(
            state.position[1] > floor_y - depth,
            "{case}: a particle at {:?} went through the floor",
            state.position
        );
        assert!(
            state.deformation.iter().all(|value| value.is_finite()),
            "{case}"
        );
    }
}

#[test]
fn stiff_and_extreme_solids_stay_finite_and_bounded_or_are_typed_errors() {
    // Small discs (radius 0.25) dropped from 0.5 units onto a floor at y = 0.4 for 0.3 s.
    let run = |material: Material, speed: f64| -> Result<Solver, MpmError> {
        let settings = Settings {
            max_substeps: 10_000,
            ..Settings::default()
        };
        let mut solver = Solver::new(grid(40, 0.05), vec![material], &[floor(0.4, 0.5)], settings)?;
        add_disc(&mut solver, 0, [1.0, 1.15], 0.25, [0.0, -speed]);
        solver.advance(0.3)?;
        Ok(solver)
    };
    let dx = 0.05;
    // Young's modulus over five orders of magnitude; the stiffest needs more substeps than the
    // limit allows, which is a typed error naming the stable step, not a slow or exploding run.
    for youngs_modulus in [10.0, 1e2, 1e3, 1e4, 1e5] {
        let case = format!("E {youngs_modulus}");
        match run(solid(youngs_modulus, 0.3, f64::INFINITY), 0.0) {
            Ok(solver) => assert_sane(&solver, 10.0, 0.4, dx, &case),
            Err(error) => panic!("{case}: {error}"),
        }
    }
    match run(solid(1e6, 0.3, f64::INFINITY), 0.0) {
        Err(MpmError::TooManySubsteps { .. }) => {}
        Err(error) => panic!("E 1e6: {error}"),
        Ok(solver) => panic!("E 1e6 in {} substeps", solver.counters().substeps),
    }
    let cases = [
        (
            "nearly incompressible",
            solid(1e3, 0.49, f64::INFINITY),
            0.0,
        ),
        ("yield stress 0", solid(1e3, 0.3, 0.0), 0.0),
        ("yield stress 1e-9", solid(1e3, 0.3, 1e-9), 0.0),
        ("yield stress 1e12", solid(1e3, 0.3, 1e12), 0.0),
        ("impact at 30 units/s (×10)", solid(1e3, 0.3, 20.0), 30.0),
        ("rigid impact at 30 units/s", RIGID, 30.0),
    ];
    for (case, material, speed) in cases {
        let solver = run(material, speed).unwrap_or_else(|error| panic!("{case}: {error}"));
        assert_sane(&solver, speed + 10.0, 0.4, dx, case);
    }
}

#[test]
fn a_soft_disc_wedged_in_a_v_under_a_rigid_one_stays_put_and_finite() {
    // A soft disc in a 90° V of two walls, a rigid disc dropped on it: both come to rest.
    let wall = |normal: [f64; 2]| Collider {
        shape: Shape::HalfPlane {
            point: [1.5, 0.4],
            normal,
        },
        boundary: Boundary::Separate { friction: 0.3 },
    };
    let side = std::f64::consts::FRAC_1_SQRT_2;
    let mut solver = Solver::new(
        grid(60, 0.05),
        vec![solid(1e3, 0.3, f64::INFINITY), RIGID],
        &[wall([side, side]), wall([-side, side])],
        Settings::default(),
    )
    .unwrap();
    add_disc(
        &mut solver,
        0,
        [1.5, 0.4 + 0.5 * 2f64.sqrt()],
        0.5,
        [0.0; 2],
    );
    add_disc(
        &mut solver,
        1,
        [1.5, 0.4 + 0.5 * 2f64.sqrt() + 0.5 + 0.4 + 0.05],
        0.4,
        [0.0; 2],
    );
    solver.advance(1.5).unwrap();
    let (soft, soft_velocity) = centre(&solver, 0);
    let rigid = &solver.rigid_bodies()[0];
    // Measured: the soft disc sits at (1.487, 1.087), moving 0.04 units/s; the rigid one rolls
    // off its top (an unstable balance) touching it, centres 0.905 apart (radii sum 0.9).
    assert!(
        soft_velocity[0].hypot(soft_velocity[1]) < 0.1,
        "{soft_velocity:?}"
    );
    assert!(
        (soft[1] - 1.107).abs() < 0.05,
        "the soft disc left the V: {soft:?}"
    );
    let apart = (rigid.center[0] - soft[0]).hypot(rigid.center[1] - soft[1]);
    assert!(
        apart > 0.85,
        "the rigid disc sank into the soft one: {apart}"
    );
    assert_sane(&solver, 2.0, 0.4, 0.05, "wedge");
    assert_eq!(solver.counters().clamped, 0);
}

#[test]
fn a_resting_rigid_disc_neither_sinks_nor_turns_and_momentum_is_kept_in_flight() {
    let mut solver = Solver::new(
        grid(48, 0.05),
        vec![RIGID],
        &[floor(0.4, 0.5)],
        Settings::default(),
    )
    .unwrap();
    add_disc(&mut solver, 0, [1.2, 0.9], 0.5, [0.0; 2]);
    solver.advance(1.0).unwrap();
    let body = &solver.rigid_bodies()[0];
    // It sits on the floor (y = 0.4 + radius) where it was put, exactly.
    assert!((body.center[1] - 0.9).abs() < 1e-9, "{:?}", body.center);
    assert!((body.center[0] - 1.2).abs() < 1e-9, "{:?}", body.center);
    assert!(body.angle.abs() < 1e-12 && body.angular_velocity.abs() < 1e-12);
    // Spinning and drifting without gravity or walls: the body keeps both.
    let settings = Settings {
        gravity: [0.0, 0.0],
        ..Settings::default()
    };
    let mut solver = Solver::new(grid(48, 0.05), vec![RIGID], &[], settings).unwrap();
    let points = disc_lattice([1.2, 1.2], 0.5, 0.025);
    solver
        .add_rigid_body(0, 0.5, &points, [0.3, -0.2], 4.0, 0.025 * 0.025)
        .unwrap();
    solver.advance(0.5).unwrap();
    let body = &solver.rigid_bodies()[0];
    assert!((body.center[0] - 1.35).abs() < 1e-9 && (body.center[1] - 1.1).abs() < 1e-9);
    assert!((body.velocity[0] - 0.3).abs() < 1e-12 && (body.velocity[1] + 0.2).abs() < 1e-12);
    assert!((body.angular_velocity - 4.0).abs() < 1e-12);
    assert!((body.angle - 2.0).abs() < 1e-9);
}

/// Total momentum: the deforming particles' plus the rigid discs' (their markers carry none).
fn momentum(solver: &Solver) -> [f64; 2] {
    let mut total = [0.0; 2];
    for (state, material, mass) in solver.particles_by_id() {
        if solver.materials()[material].scatters() {
            total[0] += mass * state.velocity[0];
            total[1] += mass * state.velocity[1];
        }
    }
    for body in solver.rigid_bodies() {
        total[0] += body.mass * body.velocity[0];
        total[1] += body.mass * body.velocity[1];
    }
    total
}

#[test]
fn a_rigid_and_a_soft_disc_collide_keeping_momentum_and_mass() {
    let settings = Settings {
        gravity: [0.0, 0.0],
        ..Settings::default()
    };
    let mut solver = Solver::new(
        grid(64, 0.05),
        vec![solid(800.0, 0.3, 30.0), RIGID],
        &[],
        settings,
    )
    .unwrap();
    let soft_count = add_disc(&mut solver, 0, [1.0, 1.6], 0.5, [2.0, 0.0]);
    let rigid_count = add_disc(&mut solver, 1, [2.2, 1.4], 0.4, [-1.0, 0.0]);
    let mass = solver.total_mass();
    let before = momentum(&solver);
    solver.advance(0.8).unwrap();
    let after = momentum(&solver);
    let body = &solver.rigid_bodies()[0];
    // They met and bounced: the rigid disc now moves right, and it spins from the off-centre hit.
    assert!(body.velocity[0] > 0.0, "{:?}", body.velocity);
    assert!(
        body.angular_velocity.abs() > 0.01,
        "{}",
        body.angular_velocity
    );
    for axis in 0..2 {
        assert!(
            (after[axis] - before[axis]).abs() < 1e-9,
            "momentum {before:?} -> {after:?}"
        );
    }
    assert_eq!(solver.particle_count(), soft_count + rigid_count);
    assert_eq!(solver.total_mass().to_bits(), mass.to_bits());
    // The soft disc keeps its area (Σ J·V, elastic with a little plastic flow, which keeps
    // volume) to within 2%.
    let area: f64 = solver
        .particles_by_id()
        .iter()
        .filter(|(_, material, _)| *material == 0)
        .map(|(state, _, mass)| state.volume_ratio * mass)
        .sum();
    let initial = soft_count as f64 * 0.025 * 0.025;
    assert!(
        (area / initial - 1.0).abs() < 0.02,
        "area {area} of {initial}"
    );
}

/// Every particle's state and every disc's pose, as bytes.
fn solid_bytes(solver: &Solver) -> Vec<u8> {
    let mut bytes = Vec::new();
    for (state, material, _) in solver.particles_by_id() {
        let ratio = [state.volume_ratio];
        let values = state
            .position
            .iter()
            .chain(&state.velocity)
            .chain(&state.affine)
            .chain(&state.deformation)
            .chain(&ratio);
        for value in values {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        bytes.extend_from_slice(&(material as u64).to_le_bytes());
    }
    for body in solver.rigid_bodies() {
        let pose = [body.angle, body.angular_velocity];
        for value in body.center.iter().chain(&body.velocity).chain(&pose) {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
    }
    bytes
}

#[test]
fn solids_liquid_and_rigid_disc_give_the_same_bytes_serial_and_parallel() {
    let run = |threads| {
        let settings = Settings {
            threads,
            ..Settings::default()
        };
        let ramp = Collider {
            shape: Shape::Capsule {
                a: [0.3, 1.4],
                b: [1.6, 0.8],
                radius: 0.05,
            },
            boundary: Boundary::Separate { friction: 0.4 },
        };
        let materials = vec![
            solid(600.0, 0.3, f64::INFINITY),
            solid(600.0, 0.3, 15.0),
            RIGID,
            Material::Liquid(LiquidMaterial {
                density: 1.0,
                bulk_modulus: 300.0,
                viscosity: 0.0,
            }),
        ];
        let mut solver = Solver::new(
            grid(64, 0.05),
            materials,
            &[ramp, floor(0.3, 0.5)],
            settings,
        )
        .unwrap();
        add_disc(&mut solver, 0, [0.7, 1.8], 0.3, [0.0; 2]);
        add_disc(&mut solver, 1, [1.4, 1.9], 0.3, [-0.5, 0.0]);
        add_disc(&mut solver, 2, [2.3, 1.2], 0.3, [-1.0, 0.0]);
        add_disc(&mut solver, 3, [2.6, 2.2], 0.25, [0.0; 2]);
        solver.advance(0.4).unwrap();
        solid_bytes(&solver)
    };
    let serial = run(1);
    assert_eq!(serial, run(2));
    assert_eq!(serial, run(3));
    // Golden hash: the solver's bytes for this scene. A change means the physics changed; update
    // it only with a reason in the commit message.
    assert_eq!(
        blake3::hash(&serial).to_hex().to_string(),
        "f7c3bc6e6e5e604c8c5827727d6f498d8087b9e0ebcae009a326a574d992fb35"
    );
}
