//! The solver against known answers: free fall is the integrator's closed form, a ball comes to
//! rest on a floor at its radius, the elastic ball springs back higher than the rigid one and the
//! plastic one keeps a dent, momentum is kept in a collision without gravity, a rigid ball keeps
//! its shape and rolls down a slope, nothing passes through a slab at the fastest speeds, and
//! the bytes of a run never change.

use super::*;
use crate::physics::vector3::{self as matrix, IDENTITY};

const RADIUS: f64 = 0.5;

/// A floor slab 0.2 thick whose top face is at `y = 0`, from `x = −20` to `20`.
fn floor() -> Slab {
    Slab {
        start: [-20.0, -0.1],
        end: [20.0, -0.1],
        thickness: 0.2,
    }
}

fn world(slabs: Vec<Slab>) -> SoftBodyWorld {
    SoftBodyWorld::new(SoftBodyParameters::default(), slabs).unwrap()
}

/// The centre's height after each update, for `updates` updates of body 0.
fn heights(world: &mut SoftBodyWorld, updates: usize) -> Vec<f64> {
    (0..updates)
        .map(|_| {
            world.step().unwrap();
            world.bodies()[0].centre()[1]
        })
        .collect()
}

#[test]
fn free_fall_is_the_integrators_closed_form() {
    // Symplectic Euler with substep h: after k substeps from rest, y = y₀ + g h² k(k+1)/2.
    let mut world = world(Vec::new());
    world
        .add_sphere([0.0, 10.0, 0.0], RADIUS, 1.0, ELASTIC)
        .unwrap();
    let parameters = SoftBodyParameters::default();
    let h = parameters.update_seconds / parameters.substeps as f64;
    for update in 1..=30 {
        world.step().unwrap();
        let k = (update * parameters.substeps) as f64;
        let expected = 10.0 + GRAVITY * h * h * k * (k + 1.0) / 2.0;
        let centre = world.bodies()[0].centre();
        assert!(
            (centre[1] - expected).abs() < 1e-9,
            "update {update}: {centre:?}"
        );
        assert!(centre[0].abs() < 1e-12 && centre[2].abs() < 1e-12);
    }
    // And the shape is untouched: a free body's goal is its rest shape.
    let deformation = world.bodies()[0].deformation();
    assert!(matrix::distance(&deformation, &IDENTITY) < 1e-9);
}

#[test]
fn a_ball_comes_to_rest_on_the_floor_at_its_radius() {
    for material in [RIGID, ELASTIC, PLASTIC] {
        let mut world = world(vec![floor()]);
        world
            .add_sphere([0.0, 1.5, 0.0], RADIUS, 1.0, material)
            .unwrap();
        let last_second = heights(&mut world, 600).split_off(540);
        let body = &world.bodies()[0];
        let radius = world.parameters().particle_radius;
        let lowest = body
            .positions()
            .iter()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min);
        // Touching the floor (the lowest particle's sphere on it, within 1% of a radius) …
        assert!(
            (lowest - radius).abs() < 0.01 * radius,
            "{material:?}: lowest {lowest}"
        );
        // … at rest: over the last second the centre stays within 0.01 units (the soft balls
        // keep a jitter of a few thousandths, under a pixel) …
        let range = last_second.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
            - last_second.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        assert!(range < 0.01, "{material:?}: centre range {range}");
        // … and still round enough that the centre is near one radius up.
        let centre = body.centre()[1];
        assert!(
            (centre - RADIUS).abs() < 0.15 * RADIUS,
            "{material:?}: centre {centre}"
        );
    }
}

/// Drops a ball of `material` from 3 units onto the floor; returns the highest the centre gets
/// after it first rebounds (upward speed after the first contact), and the body afterwards.
fn rebound(material: SoftMaterial) -> (f64, Body) {
    let mut world = world(vec![floor()]);
    world
        .add_sphere([0.0, 3.0, 0.0], RADIUS, 1.0, material)
        .unwrap();
    let mut rebounded = false;
    let mut highest = f64::NEG_INFINITY;
    for _ in 0..120 {
        world.step().unwrap();
        let body = &world.bodies()[0];
        if body.centre_velocity()[1] > 0.0 && body.centre()[1] < 1.0 {
            rebounded = true;
        }
        if rebounded {
            highest = highest.max(body.centre()[1]);
        }
    }
    (highest, world.bodies()[0].clone())
}

#[test]
fn the_elastic_ball_springs_back_higher_than_the_rigid_and_the_plastic_keeps_a_dent() {
    let (elastic, elastic_body) = rebound(ELASTIC);
    let (rigid, rigid_body) = rebound(RIGID);
    let (plastic, plastic_body) = rebound(PLASTIC);
    // The rigid ball stops on contact (position-based contact has no restitution); the elastic
    // one stores the squash and gives it back.
    assert!(elastic > rigid + 0.1, "elastic {elastic}, rigid {rigid}");
    assert!(
        elastic > plastic + 0.1,
        "elastic {elastic}, plastic {plastic}"
    );
    // Only the plastic ball's rest shape changed, and within its cap.
    let dent = matrix::distance(&plastic_body.plastic_deformation(), &IDENTITY);
    assert!(dent > 0.05 && dent <= 0.622 + 1e-9, "dent {dent}");
    for body in [&elastic_body, &rigid_body] {
        assert_eq!(body.plastic_deformation(), IDENTITY);
    }
    // The dent is a squash: the plastic ball is lower than it is wide.
    let spread = |axis: usize| {
        let values = plastic_body.positions().iter().map(|p| p[axis]);
        values.clone().fold(f64::NEG_INFINITY, f64::max) - values.fold(f64::INFINITY, f64::min)
    };
    assert!(
        spread(1) < 0.95 * spread(0),
        "height {} width {}",
        spread(1),
        spread(0)
    );
}

#[test]
fn momentum_is_kept_in_a_collision_without_gravity() {
    let parameters = SoftBodyParameters {
        gravity: 0.0,
        ..SoftBodyParameters::default()
    };
    let mut world = SoftBodyWorld::new(parameters, Vec::new()).unwrap();
    let a = world
        .add_sphere([-1.0, 0.0, 0.0], RADIUS, 1.0, ELASTIC)
        .unwrap();
    let b = world
        .add_sphere([1.0, 0.1, 0.0], RADIUS, 3.0, RIGID)
        .unwrap();
    world.body_mut(a).unwrap().set_velocity([3.0, 0.0, 0.0]);
    world.body_mut(b).unwrap().set_velocity([-1.0, 0.0, 0.0]);
    let momentum = |world: &SoftBodyWorld| {
        world.bodies().iter().fold([0.0; 3], |acc, body| {
            let mass = body.particle_mass * body.positions().len() as f64;
            matrix::add(acc, matrix::scale(body.centre_velocity(), mass))
        })
    };
    let before = momentum(&world);
    for _ in 0..90 {
        world.step().unwrap();
    }
    let after = momentum(&world);
    assert!(
        matrix::norm(matrix::sub(after, before)) < 1e-9,
        "{before:?} → {after:?}"
    );
    // They met and came apart: a is now moving left of b and away from it.
    let (ca, cb) = (world.bodies()[a].centre(), world.bodies()[b].centre());
    assert!(ca[0] < cb[0]);
    let gap = matrix::norm(matrix::sub(cb, ca));
    assert!(gap > 2.0 * RADIUS - 0.02, "gap {gap}");
    assert!(world.bodies()[a].centre_velocity()[0] < world.bodies()[b].centre_velocity()[0]);
}

#[test]
fn a_rigid_ball_rolls_down_a_slope_and_keeps_its_shape() {
    // A 30° slope through the origin, 0.2 thick, its top face 0.1 above the centre line.
    let angle = 30.0_f64.to_radians();
    let (c, s) = (angle.cos(), angle.sin());
    let slope = Slab {
        start: [-10.0 * c, 10.0 * s],
        end: [10.0 * c, -10.0 * s],
        thickness: 0.2,
    };
    let normal = [s, c];
    let start = [
        -2.0 * c + (0.1 + RADIUS) * normal[0],
        2.0 * s + (0.1 + RADIUS) * normal[1],
        0.0,
    ];
    let mut world = world(vec![slope]);
    world.add_sphere(start, RADIUS, 1.0, RIGID).unwrap();
    let original: Vec<_> = world.bodies()[0].positions().to_vec();
    let updates: u16 = 60;
    for _ in 0..updates {
        world.step().unwrap();
    }
    let body = &world.bodies()[0];
    let moved = matrix::sub(body.centre(), start);
    let along = moved[0] * c - moved[1] * s;
    let t = f64::from(updates) / 60.0;
    // Down the slope, slower than frictionless sliding (g sin θ t²/2) and faster than a fifth
    // of it: rolling without slipping would be 5/7 of it.
    let sliding = 0.5 * 9.8 * s * t * t;
    assert!(
        along < sliding && along > 0.2 * sliding,
        "{along} of {sliding}"
    );
    // It rotated (rolled), and every pairwise distance is as it was within 1%.
    let rotation = body.rotation();
    assert!(
        matrix::distance(&rotation, &IDENTITY) > 0.5,
        "no rolling: {rotation:?}"
    );
    for (i, j) in [(0, 1), (5, 60), (20, 90), (40, 41)] {
        let now = matrix::norm(matrix::sub(body.positions()[i], body.positions()[j]));
        let then = matrix::norm(matrix::sub(original[i], original[j]));
        assert!((now - then).abs() < 0.01 * then, "{i}-{j}: {then} → {now}");
    }
}

#[test]
fn nothing_passes_through_a_slab_at_the_fastest_speeds() {
    // A 7-unit drop onto the thinnest slab, and a ball fired at the speed cap into a wall.
    let wall = Slab {
        start: [0.0, -3.0],
        end: [0.0, 3.0],
        thickness: 0.2,
    };
    for material in [RIGID, ELASTIC, PLASTIC] {
        let mut world = world(vec![floor(), wall.clone()]);
        world
            .add_sphere([-3.0, 7.6, 0.0], RADIUS, 1.0, material)
            .unwrap();
        let fired = world
            .add_sphere([-2.0, 1.0, 0.0], RADIUS, 1.0, material)
            .unwrap();
        world
            .body_mut(fired)
            .unwrap()
            .set_velocity([30.0, 0.0, 0.0]);
        for _ in 0..180 {
            world.step().unwrap();
            for body in world.bodies() {
                for position in body.positions() {
                    assert!(
                        position[1] > 0.0 && position[0] < -0.1,
                        "{material:?}: {position:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn settings_that_would_let_a_particle_tunnel_are_refused() {
    let parameters = SoftBodyParameters {
        max_speed: 100.0,
        ..SoftBodyParameters::default()
    };
    let error = SoftBodyWorld::new(parameters, vec![floor()]).unwrap_err();
    assert!(matches!(
        error,
        SoftBodyError::Setting {
            name: "max_speed",
            ..
        }
    ));
    let error = world(Vec::new())
        .add_sphere([0.0; 3], 0.2, 1.0, RIGID)
        .unwrap_err();
    assert!(matches!(
        error,
        SoftBodyError::Setting {
            name: "sphere radius",
            ..
        }
    ));
}

/// The release's kind of scene: a floor, a slanted and a vertical floating wall, a ramp, three
/// balls of the three materials.
fn stadium() -> SoftBodyWorld {
    let mut world = world(vec![
        floor(),
        Slab {
            start: [-2.5, 4.04],
            end: [0.5, 1.2],
            thickness: 0.4,
        },
        Slab {
            start: [2.5, 4.04],
            end: [2.5, 1.2],
            thickness: 0.4,
        },
        Slab {
            start: [4.0, -0.07],
            end: [7.0, 4.04],
            thickness: 0.2,
        },
    ]);
    world
        .add_sphere([-1.0, 6.0, 0.0], RADIUS, 1.0, ELASTIC)
        .unwrap();
    world
        .add_sphere([5.5, 5.5, 0.0], RADIUS, 1.0, RIGID)
        .unwrap();
    world
        .add_sphere([2.0, 6.5, 0.0], RADIUS, 1.0, PLASTIC)
        .unwrap();
    world
}

fn run_bytes(updates: usize) -> Vec<u8> {
    let mut world = stadium();
    let mut bytes = Vec::new();
    for _ in 0..updates {
        world.step().unwrap();
        for body in world.bodies() {
            for value in body.positions().iter().chain(body.velocities()).flatten() {
                bytes.extend_from_slice(&value.to_le_bytes());
            }
        }
    }
    bytes
}

#[test]
fn a_stadium_run_is_deterministic_and_its_bytes_never_change() {
    let bytes = run_bytes(300);
    assert_eq!(bytes, run_bytes(300));
    let digest = crate::util::content_hash(&bytes);
    assert_eq!(
        digest, "2f80570ac776b9e50ba38db681d3f5ba8d60e55df28df7751660acfcf2dc16c1",
        "the solver's output changed"
    );
}

/// The plastic ball's dent (Frobenius distance of its rest shape from the original) after a drop
/// of its centre from `height` units above its resting height.
fn dent_after_drop(height: f64) -> f64 {
    let mut world = world(vec![floor()]);
    world
        .add_sphere([0.0, RADIUS + height, 0.0], RADIUS, 1.0, PLASTIC)
        .unwrap();
    heights(&mut world, 150);
    matrix::distance(&world.bodies()[0].plastic_deformation(), &IDENTITY)
}

#[test]
fn the_plastic_dent_grows_with_the_drop_height() {
    let dents: Vec<f64> = [0.5, 1.5, 3.0, 6.0].map(dent_after_drop).to_vec();
    // Measured: 0.0, 0.05, 0.10, 0.16 (a drop of 0.5 stays below the yield).
    assert!(dents[0] < 1e-9, "{dents:?}");
    for pair in dents.windows(2).skip(1) {
        assert!(pair[1] > pair[0] + 0.02, "{dents:?}");
    }
    assert!(dents[3] <= 0.622 + 1e-9, "{dents:?}");
}

/// Kinetic plus potential energy of every particle, J (masses in kg, gravity 9.8).
fn energy(world: &SoftBodyWorld) -> f64 {
    world
        .bodies()
        .iter()
        .map(|body| {
            body.positions()
                .iter()
                .zip(body.velocities())
                .map(|(p, v)| body.particle_mass * (0.5 * matrix::dot(*v, *v) - GRAVITY * p[1]))
                .sum::<f64>()
        })
        .sum()
}

#[test]
fn energy_never_grows_without_input() {
    for material in [RIGID, ELASTIC, PLASTIC] {
        let mut world = world(vec![floor()]);
        world
            .add_sphere([0.0, 3.0, 0.0], RADIUS, 1.0, material)
            .unwrap();
        let start = energy(&world);
        let mut highest = start;
        for _ in 0..300 {
            world.step().unwrap();
            highest = highest.max(energy(&world));
        }
        // Symplectic Euler's free fall carries a discretisation term of g²h²/2 per unit mass at
        // most; allow 0.1% of the drop's energy.
        assert!(
            highest <= start + 1e-3 * start.abs(),
            "{material:?}: {start} → {highest}"
        );
        assert!(energy(&world) < start, "{material:?}: nothing was lost");
    }
}

/// Distance a rigid ball travels down a 30° slope of friction `friction` in one second.
fn slope_travel(friction: f64) -> f64 {
    let angle = 30.0_f64.to_radians();
    let (c, s) = (angle.cos(), angle.sin());
    let slope = Slab {
        start: [-20.0 * c, 20.0 * s],
        end: [20.0 * c, -20.0 * s],
        thickness: 0.2,
    };
    let parameters = SoftBodyParameters {
        static_friction: friction,
        dynamic_friction: friction,
        ..SoftBodyParameters::default()
    };
    let mut world = SoftBodyWorld::new(parameters, vec![slope]).unwrap();
    // Resting on the slope: centre one radius (and half the thickness) along its normal.
    let start = [(0.1 + RADIUS) * s, (0.1 + RADIUS) * c, 0.0];
    world.add_sphere(start, RADIUS, 1.0, RIGID).unwrap();
    for _ in 0..60 {
        world.step().unwrap();
    }
    let moved = matrix::sub(world.bodies()[0].centre(), start);
    moved[0] * c - moved[1] * s
}

#[test]
fn a_ball_on_a_slope_slides_without_friction_and_rolls_with_it() {
    let g_sin = 9.8 * 0.5;
    // Without friction: sliding, g sin θ t²/2.
    let sliding = slope_travel(0.0);
    assert!(
        (sliding / (0.5 * g_sin) - 1.0).abs() < 0.05,
        "sliding {sliding}"
    );
    // With ample friction it rolls: a smooth ball of this inertia (shells at 0.19 and 0.38,
    // contact radius 0.5: I/(m R²) = 0.324) would accelerate at 0.755 g sin θ. A ball of
    // particles rolls over its 72 surface particles as over the corners of a polygon, losing
    // energy at each (measured: 0.50 g sin θ), as a PBD particle ball does.
    let rolling = slope_travel(1.0);
    let share = rolling / (0.5 * g_sin);
    assert!(
        share > 0.4 && share < 0.755,
        "rolling {rolling} ({share} of sliding)"
    );
}

#[test]
fn extreme_materials_and_speeds_stay_finite_and_bounded() {
    let puddle = SoftMaterial {
        deformation_resistance: 0.0,
        plasticity: None,
    };
    let always_yields = SoftMaterial {
        deformation_resistance: 0.136,
        plasticity: Some(Plasticity {
            yield_strain: 0.0,
            ..PLASTIC.plasticity.unwrap()
        }),
    };
    let never_yields = SoftMaterial {
        deformation_resistance: 0.136,
        plasticity: Some(Plasticity {
            yield_strain: 1e9,
            ..PLASTIC.plasticity.unwrap()
        }),
    };
    // A V of a wall and a ramp 0.9 apart at the top, narrower than the ball below.
    let wedge = vec![
        floor(),
        Slab {
            start: [-0.55, 0.0],
            end: [-0.55, 3.0],
            thickness: 0.2,
        },
        Slab {
            start: [0.0, 0.0],
            end: [1.5, 3.0],
            thickness: 0.2,
        },
    ];
    for material in [puddle, RIGID, always_yields, never_yields, ELASTIC] {
        let mut world = world(wedge.clone());
        let dropped = world
            .add_sphere([0.2, 4.0, 0.0], RADIUS, 1.0, material)
            .unwrap();
        let fired = world
            .add_sphere([-5.0, 6.0, 0.0], RADIUS, 1.0, material)
            .unwrap();
        world
            .body_mut(dropped)
            .unwrap()
            .set_velocity([0.0, -120.0, 0.0]);
        world
            .body_mut(fired)
            .unwrap()
            .set_velocity([120.0, -60.0, 0.0]);
        for _ in 0..240 {
            world.step().unwrap();
        }
        for body in world.bodies() {
            assert_eq!(body.positions().len(), SPHERE_PARTICLES);
            let mass = body.particle_mass * body.positions().len() as f64;
            assert!((mass - 1.0).abs() < 1e-12, "{material:?}: mass {mass}");
            for p in body.positions() {
                assert!(
                    p.iter().all(|v| v.is_finite() && v.abs() < 50.0),
                    "{material:?}: {p:?}"
                );
                assert!(p[1] > 0.0, "{material:?}: below the floor at {p:?}");
            }
        }
        if material == never_yields {
            assert_eq!(world.bodies()[0].plastic_deformation(), IDENTITY);
        }
    }
}
