//! The solver against known answers: a fluid at rest stays at rest with a flat surface, denser
//! fluid sinks, particles are only added by emitters, nothing crosses a thin collider, viscosity
//! slows a flow, surface tension rounds a drop, and the bytes of a run never change.

use super::*;

const WATER: FluidMaterial = FluidMaterial {
    rest_density: 1600.0,
    viscosity: 0.02,
    surface_tension: 1.0,
};

fn wall(start: [f64; 2], end: [f64; 2]) -> Collider {
    Collider {
        start,
        end,
        half_thickness: 0.05,
        friction: 0.3,
        stickiness: 0.03,
    }
}

/// A box `width` wide with its inner floor at `y = 0` and inner walls at `x = 0` and `width`.
fn tank(width: f64) -> Vec<Collider> {
    vec![
        wall([-0.5, -0.05], [width + 0.5, -0.05]),
        wall([-0.05, -0.05], [-0.05, 3.0]),
        wall([width + 0.05, -0.05], [width + 0.05, 3.0]),
    ]
}

fn world(
    fluids: Vec<FluidMaterial>,
    colliders: Vec<Collider>,
    emitters: Vec<Emitter>,
) -> FluidWorld {
    FluidWorld::new(FluidParameters::default(), fluids, colliders, emitters, 7).unwrap()
}

/// Fills `columns × rows` lattice sites of the spacing from `corner` with `fluid`.
fn block(world: &mut FluidWorld, fluid: usize, corner: [f64; 2], columns: usize, rows: usize) {
    let s = FluidParameters::default().spacing;
    for row in 0..rows {
        for column in 0..columns {
            world.add_particle(
                fluid,
                [
                    corner[0] + (column as f64 + 0.5) * s,
                    corner[1] + (row as f64 + 0.5) * s,
                ],
                [0.0, 0.0],
            );
        }
    }
}

/// An emitter of `fluid` with the release's edge, speeds and opening update, at (0.5, 1).
fn release_emitter(fluid: usize, direction: [f64; 2], capacity: usize) -> Emitter {
    Emitter {
        fluid,
        centre: [0.5, 1.0],
        direction,
        width: 0.5,
        speed: 0.7,
        random_velocity: 0.4,
        capacity,
        opens_at: 2,
    }
}

fn run(world: &mut FluidWorld, updates: usize) {
    for _ in 0..updates {
        world.step().unwrap();
    }
}

fn mean_height(world: &FluidWorld, fluid: usize) -> f64 {
    let heights: Vec<f64> = world
        .positions()
        .iter()
        .zip(world.fluid_of())
        .filter(|(_, f)| **f == fluid)
        .map(|(p, _)| p[1])
        .collect();
    heights.iter().sum::<f64>() / heights.len() as f64
}

#[test]
fn a_fluid_at_rest_stays_at_rest_with_a_flat_surface() {
    let s = FluidParameters::default().spacing;
    let mut world = world(vec![WATER], tank(20.0 * s), Vec::new());
    block(&mut world, 0, [0.0, 0.0], 20, 16);
    run(&mut world, 180);
    let fastest = world
        .velocities()
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0, f64::max);
    let mean = world
        .velocities()
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .sum::<f64>()
        / 320.0;
    let mut speeds: Vec<f64> = world
        .velocities()
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .collect();
    speeds.sort_by(f64::total_cmp);
    let percentile_99 = speeds[speeds.len() * 99 / 100];
    eprintln!("at rest: mean speed {mean}, 99th percentile {percentile_99}, fastest {fastest}");
    // Position-based fluids jitter at rest, most at the free surface: the stated tolerance is a
    // mean speed under 0.1 units/s and 99% of particles under 0.4 (a free fall of one spacing
    // reaches 0.49).
    assert!(
        mean < 0.1 && percentile_99 < 0.4,
        "mean {mean}, 99th percentile {percentile_99} units/s"
    );
    // Compression stays within the solver's tolerance (12 iterations a update: 5%).
    let ratios = world.density_ratios();
    let densest = ratios.iter().copied().fold(0.0, f64::max);
    eprintln!("at rest: densest {densest}");
    assert!(densest < 1.05, "densest particle {densest} of rest");
    // The free surface: the highest particle of each column, level within a spacing.
    let mut tops = [f64::MIN; 20];
    for p in world.positions() {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to the tank's 20 columns"
        )]
        let column = ((p[0] / s).floor().clamp(0.0, 19.0)) as usize;
        tops[column] = tops[column].max(p[1]);
    }
    let level = tops.iter().sum::<f64>() / 20.0;
    let spread = (tops.iter().map(|t| (t - level) * (t - level)).sum::<f64>() / 20.0).sqrt();
    eprintln!("at rest: surface at {level}, column tops spread {spread}");
    // Level: the columns' tops scatter by less than half a spacing (RMS) round their mean, and
    // the volume holds: the top row's centres sit within a spacing of where 16 rows of the rest
    // spacing put them (0.3875).
    assert!(
        spread < 0.5 * s,
        "column tops spread {spread} round {level}"
    );
    assert!((level - 15.5 * s).abs() < s, "surface at {level}");
}

#[test]
fn the_denser_fluid_sinks_through_the_lighter_one() {
    let s = FluidParameters::default().spacing;
    let light = FluidMaterial {
        rest_density: 1200.0,
        viscosity: 0.02,
        surface_tension: 1.0,
    };
    let heavy = FluidMaterial {
        rest_density: 5400.0,
        viscosity: 0.02,
        surface_tension: 1.0,
    };
    let mut world = world(vec![light, heavy], tank(16.0 * s), Vec::new());
    block(&mut world, 0, [0.0, 0.0], 16, 8);
    block(&mut world, 1, [0.0, 8.0 * s], 16, 8);
    assert!(mean_height(&world, 1) > mean_height(&world, 0));
    run(&mut world, 600);
    let (light_y, heavy_y) = (mean_height(&world, 0), mean_height(&world, 1));
    assert!(heavy_y < light_y, "heavy at {heavy_y}, light at {light_y}");
}

#[test]
fn only_emitters_add_particles_and_all_stay_in_the_tank() {
    let width = 1.0;
    let emitter = release_emitter(0, [0.0, -1.0], 300);
    let mut world = world(vec![WATER], tank(width), vec![emitter]);
    let mut last = 0;
    for update in 0..240 {
        world.step().unwrap();
        let count = world.positions().len();
        assert!(count >= last, "update {update}: {count} after {last}");
        if update < 2 {
            assert_eq!(count, 0, "the emitter opens at update 2");
        }
        last = count;
    }
    assert_eq!(last, 300);
    for p in world.positions() {
        assert!(
            p[0] > 0.0 && p[0] < width && p[1] > 0.0,
            "{p:?} left the tank"
        );
    }
}

#[test]
fn nothing_crosses_a_thin_stick_at_ten_times_the_emitter_speed() {
    let stick = Collider {
        start: [-1.0, 0.5],
        end: [1.0, 0.5],
        half_thickness: 0.01,
        friction: 0.4,
        stickiness: 0.1,
    };
    let mut world = world(vec![WATER], vec![stick], Vec::new());
    for k in 0..40 {
        let x = -0.5 + f64::from(k) * 0.025;
        world.add_particle(0, [x, 0.52 + 0.01 * f64::from(k % 3)], [0.3, -7.0]);
    }
    run(&mut world, 20);
    for p in world.positions() {
        assert!(p[1] > 0.5, "{p:?} crossed the stick");
    }
}

#[test]
fn a_sticky_fluid_runs_down_a_ramp_slower_than_a_non_sticky_one() {
    let angle = 35.0_f64.to_radians();
    let ramp = |friction| Collider {
        start: [0.0, 2.0],
        end: [3.0 * angle.cos(), 2.0 - 3.0 * angle.sin()],
        half_thickness: 0.075,
        friction,
        stickiness: 0.1,
    };
    let travelled = |viscosity: f64| {
        let fluid = FluidMaterial {
            rest_density: 1600.0,
            viscosity,
            surface_tension: 1.0,
        };
        let mut world = world(vec![fluid], vec![ramp(0.5)], Vec::new());
        // A blob resting just above the ramp's top.
        let s = FluidParameters::default().spacing;
        for row in 0..6 {
            for column in 0..6 {
                let along = 0.3 + f64::from(column) * s;
                let up = 0.075 + 0.5 * s + f64::from(row) * s + 0.01;
                world.add_particle(
                    0,
                    [
                        along * angle.cos() + up * angle.sin(),
                        2.0 - along * angle.sin() + up * angle.cos(),
                    ],
                    [0.0, 0.0],
                );
            }
        }
        let start: f64 = world.positions().iter().map(|p| p[0]).sum();
        run(&mut world, 90);
        let end: f64 = world.positions().iter().map(|p| p[0]).sum();
        (end - start) / 36.0
    };
    let (runny, sticky) = (travelled(0.02), travelled(10.0));
    eprintln!("down the ramp: non-sticky {runny}, sticky {sticky} units");
    assert!(runny > 0.1, "the non-sticky blob moved {runny} units");
    assert!(
        sticky < 0.8 * runny,
        "sticky {sticky} against non-sticky {runny}"
    );
}

#[test]
fn a_run_is_bit_for_bit_the_same() {
    let emitter = release_emitter(1, [0.3, -1.0], 120);
    let thick = FluidMaterial {
        rest_density: 4400.0,
        viscosity: 10.0,
        surface_tension: 1.0,
    };
    let mut world = world(vec![WATER, thick], tank(1.0), vec![emitter]);
    block(&mut world, 0, [0.0, 0.0], 10, 4);
    run(&mut world, 90);
    let mut bytes = Vec::new();
    for (p, v) in world.positions().iter().zip(world.velocities()) {
        for value in p.iter().chain(v) {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
    }
    let digest = crate::util::content_hash(&bytes);
    assert_eq!(
        digest,
        "bb70035e7ad93aff7e0211ae15ef47c2c07fe96fb760769d6e399feb087e7db6"
    );
}

#[test]
fn bad_settings_are_refused() {
    let parameters = FluidParameters {
        spacing: 0.0,
        ..FluidParameters::default()
    };
    let error = FluidWorld::new(parameters, vec![WATER], Vec::new(), Vec::new(), 1).unwrap_err();
    assert_eq!(
        error.to_string(),
        "fluid solver setting `spacing` is 0: must be positive and finite"
    );
}

/// The largest distance of a fluid's particles from their centroid over the radius of a disc of
/// their area (1 for a round drop, 1.24 for a square).
fn roughness(world: &FluidWorld) -> f64 {
    let s = FluidParameters::default().spacing;
    let points = world.positions();
    let n = points.len() as f64;
    let centre = points
        .iter()
        .fold([0.0, 0.0], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
    let farthest = points
        .iter()
        .map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]))
        .fold(0.0, f64::max);
    // The outermost particle centres lie half a spacing inside the fluid's edge.
    (farthest + 0.5 * s) / (n * s * s / std::f64::consts::PI).sqrt()
}

#[test]
fn surface_tension_rounds_a_floating_block_into_a_drop() {
    let floating = |surface_tension: f64| {
        let fluid = FluidMaterial {
            surface_tension,
            ..WATER
        };
        let parameters = FluidParameters {
            gravity: 0.0,
            ..FluidParameters::default()
        };
        let mut world =
            FluidWorld::new(parameters, vec![fluid], Vec::new(), Vec::new(), 7).unwrap();
        block(&mut world, 0, [1.0, 1.0], 20, 20);
        let square = roughness(&world);
        run(&mut world, 120);
        (square, roughness(&world), world)
    };
    let (square, still, _) = floating(0.0);
    let (_, rounded, world) = floating(1.0);
    // The corner particle sits 9.5·√2 + 0.5 spacings out, the disc's radius is 20/√π.
    let expected = (9.5 * std::f64::consts::SQRT_2 + 0.5) / (20.0 / std::f64::consts::PI.sqrt());
    eprintln!("roughness: square {square:.3}, without tension {still:.3}, with {rounded:.3}");
    assert!(
        (square - expected).abs() < 1e-9,
        "a square starts at {square:.3}"
    );
    assert!(
        still > 1.2,
        "without surface tension the block keeps its corners: {still:.3}"
    );
    assert!(
        rounded < 1.1,
        "with surface tension it becomes a drop: {rounded:.3}"
    );
    // Cohesion pulls the surface in without collapsing the drop.
    let ratios = world.density_ratios();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    assert!(
        mean < 1.05,
        "the drop is not compressed: mean number density {mean:.3}"
    );
}
