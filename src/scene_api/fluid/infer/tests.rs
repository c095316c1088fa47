//! Inference on hand-built tracks with known answers, and on the repository's generated demo
//! video (`eval/demo/fluid_slides/0`), whose truth is in its annotations.

use std::path::Path;

use super::*;
use crate::dataset::SoftBodyTrack;
use crate::dataset::fluid::FluidAnnotation;

const BLUE: &str = "Blue Fluid";
const PINK: &str = "Pink Fluid";
const GREEN: &str = "Green Fluid";

/// A cup `[x0, x1] × [-4, -3.12]` under a funnel `[x0 - 0.2, x1 + 0.2] × [-3.12, -2.75]`.
fn cup(name: &str, x0: f64, x1: f64) -> ContainerRegion {
    ContainerRegion {
        name: name.to_string(),
        cup: Rect {
            min: [x0, -4.0],
            max: [x1, -3.12],
        },
        funnel: Rect {
            min: [x0 - 0.2, -3.12],
            max: [x1 + 0.2, -2.75],
        },
    }
}

/// A scene of `fluids` with two cups (left `[-2, -1]`, right `[1, 2]`) and one stick from
/// (-1, 1) down to (1, 0).
fn scene(fluids: &[&str]) -> PerceivedFluidScene {
    PerceivedFluidScene {
        sticks: vec![StickSegment {
            name: "Red Stick".to_string(),
            start: [-1.0, 1.0],
            end: [1.0, 0.0],
            half_thickness: 0.075,
        }],
        containers: vec![
            cup("Red Container", -2.0, -1.0),
            cup("Gray Container", 1.0, 2.0),
        ],
        fluids: fluids
            .iter()
            .enumerate()
            .map(|(i, name)| {
                (
                    (*name).to_string(),
                    [f64::from(u8::try_from(i).unwrap()), 2.85],
                )
            })
            .collect(),
    }
}

/// A body whose `count` particles rest at `at(k)` in every one of `frames` frames.
fn resting(count: usize, frames: usize, at: impl Fn(usize) -> [f64; 2]) -> SoftBodyTrack {
    let frame: Vec<[f64; 3]> = (0..count)
        .map(|k| {
            let [x, y] = at(k);
            [x, y, 0.0]
        })
        .collect();
    SoftBodyTrack {
        particles: vec![frame; frames],
    }
}

/// `count` particles spread over `[x0, x1]` at heights `[y0, y1]`.
fn layer(count: usize, x: [f64; 2], y: [f64; 2]) -> SoftBodyTrack {
    #[expect(clippy::cast_precision_loss, reason = "small test counts")]
    resting(count, 3, |k| {
        let t = k as f64 / count as f64;
        [
            x[0] + t * (x[1] - x[0]),
            y[0] + ((t * 7.0).fract()) * (y[1] - y[0]),
        ]
    })
}

fn four_d(bodies: Vec<(&str, SoftBodyTrack)>) -> FourDData {
    FourDData {
        rigid_bodies: IndexMap::new(),
        soft_bodies: bodies
            .into_iter()
            .map(|(name, body)| (name.to_string(), body))
            .collect(),
    }
}

fn infer(fluids: &[&str], bodies: Vec<(&str, SoftBodyTrack)>) -> FluidInference {
    infer_fluid_properties("test", &scene(fluids), &four_d(bodies)).unwrap()
}

#[test]
fn two_fluids_stacked_in_a_cup_order_their_densities() {
    // Blue lies below pink in the left cup; green is elsewhere.
    let inference = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, layer(20, [-1.9, -1.1], [-3.95, -3.75])),
            (PINK, layer(20, [-1.9, -1.1], [-3.7, -3.5])),
            (GREEN, layer(20, [3.0, 3.5], [-3.95, -3.75])),
        ],
    );
    let density = &inference.density;
    assert_eq!(density.order(BLUE, PINK), DensityOrder::Heavier);
    assert_eq!(density.order(PINK, BLUE), DensityOrder::Lighter);
    // A later emitter's name stands for its fluid.
    assert_eq!(
        density.order("Later Emitted Pink Fluid", BLUE),
        DensityOrder::Lighter
    );
    // Never together: "can not answer".
    assert_eq!(density.order(GREEN, BLUE), DensityOrder::Unknown);
    assert_eq!(density.order(GREEN, PINK), DensityOrder::Unknown);
    assert_eq!(density.relations, [(BLUE.to_string(), PINK.to_string())]);
    let [comparison] = density.comparisons.as_slice() else {
        panic!("one comparison expected: {:?}", density.comparisons);
    };
    assert_eq!(comparison.container, "Red Container");
    assert_eq!(
        (comparison.first.particles, comparison.second.particles),
        (20, 20)
    );
    assert!((comparison.gap + 0.25).abs() < 0.03, "{comparison:?}");
    // Ranks: pink below blue by the order; green, unrelated and never layered with either,
    // is placed by the tie-break's last rule, scene order: pink and green are the candidates for
    // the lightest (pink first), then blue and green (blue first).
    let ranks: Vec<(&str, usize, f64, bool)> = inference
        .ranks
        .iter()
        .map(|r| (r.fluid.as_str(), r.rank, r.density, r.tie_broken))
        .collect();
    assert_eq!(
        ranks,
        [
            (PINK, 0, 1600.0, true),
            (BLUE, 1, 3000.0, true),
            (GREEN, 2, 4400.0, false)
        ]
    );
}

/// `count` particles spread over `[x0, x1]` at heights `[y0, y1]` at frame 0, each moving
/// `dy` units a frame over `frames` frames.
fn drifting(count: usize, frames: usize, x: [f64; 2], y: [f64; 2], dy: f64) -> SoftBodyTrack {
    let start = layer(count, x, y);
    SoftBodyTrack {
        particles: (0..frames)
            .map(|frame| {
                #[expect(clippy::cast_precision_loss, reason = "small test counts")]
                let shift = dy * frame as f64;
                start.particles[0]
                    .iter()
                    .map(|[px, py, pz]| [*px, py + shift, *pz])
                    .collect()
            })
            .collect(),
    }
}

#[test]
fn a_fluid_sinking_through_another_is_the_denser() {
    // Pink and blue end level in the left cup (the heights say nothing), but pink's particles
    // sink 0.001 units a frame through resting blue: over the last 40 frames that is 0.04,
    // 0.1 extrapolated to the truth's count, beyond the margin.
    let frames = 60;
    let sinking = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, drifting(20, frames, [-1.9, -1.1], [-3.9, -3.6], 0.0)),
            (
                PINK,
                drifting(20, frames, [-1.88, -1.08], [-3.841, -3.541], -0.001),
            ),
            (GREEN, drifting(20, frames, [3.0, 3.5], [-3.95, -3.75], 0.0)),
        ],
    );
    let density = &sinking.density;
    assert_eq!(density.order(PINK, BLUE), DensityOrder::Heavier);
    let decided: Vec<(LayerEvidence, f64)> = density
        .comparisons
        .iter()
        .filter(|comparison| comparison.heavier.is_some())
        .map(|comparison| (comparison.evidence, comparison.gap))
        .collect();
    let [(LayerEvidence::CupSinking, gap)] = decided.as_slice() else {
        panic!("only the cup's sinking decides: {:?}", density.comparisons);
    };
    // Blue minus pink: blue rose 0.1 more than pink.
    assert!((gap - 0.1).abs() < 1e-9, "{gap}");
    // Resting side by side, neither sinks: nothing decides.
    let resting = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, drifting(20, frames, [-1.9, -1.1], [-3.9, -3.6], 0.0)),
            (
                PINK,
                drifting(20, frames, [-1.88, -1.08], [-3.9, -3.6], 0.0),
            ),
            (GREEN, drifting(20, frames, [3.0, 3.5], [-3.95, -3.75], 0.0)),
        ],
    );
    assert_eq!(resting.density.order(PINK, BLUE), DensityOrder::Unknown);
}

#[test]
fn thin_or_level_layers_decide_nothing() {
    // Two pink particles are drops, not a layer; level layers within the margin say nothing
    // either.
    let thin = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, layer(20, [-1.9, -1.1], [-3.95, -3.75])),
            (PINK, layer(2, [-1.9, -1.1], [-3.7, -3.5])),
            (GREEN, layer(20, [1.1, 1.9], [-3.95, -3.75])),
        ],
    );
    assert_eq!(thin.density.order(BLUE, PINK), DensityOrder::Unknown);
    assert_eq!(thin.density.comparisons.len(), 1);
    let level = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, layer(20, [-1.9, -1.5], [-3.95, -3.6])),
            (PINK, layer(20, [-1.5, -1.1], [-3.94, -3.59])),
            (GREEN, layer(20, [3.0, 3.5], [-3.95, -3.75])),
        ],
    );
    assert_eq!(level.density.order(BLUE, PINK), DensityOrder::Unknown);
}

#[test]
fn relations_close_transitively_and_conflicts_are_undecided() {
    // Left cup: blue below pink. Right cup: pink below green. So blue is denser than green,
    // though the two never meet.
    let chain = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, layer(20, [-1.9, -1.1], [-3.95, -3.75])),
            (
                PINK,
                resting(40, 3, |k| if k < 20 { [-1.5, -3.6] } else { [1.5, -3.9] }),
            ),
            (GREEN, layer(20, [1.1, 1.9], [-3.5, -3.3])),
        ],
    );
    assert_eq!(chain.density.order(BLUE, GREEN), DensityOrder::Heavier);
    assert_eq!(chain.density.order(GREEN, BLUE), DensityOrder::Lighter);
    let ranks: Vec<&str> = chain.ranks.iter().map(|r| r.fluid.as_str()).collect();
    assert_eq!(ranks, [GREEN, PINK, BLUE]);
    assert!(chain.ranks.iter().all(|r| !r.tie_broken));

    // Blue below pink on the left, above it on the right, as many particles each way: the
    // video contradicts itself.
    let conflict = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (
                BLUE,
                resting(40, 3, |k| if k < 20 { [-1.5, -3.9] } else { [1.5, -3.5] }),
            ),
            (
                PINK,
                resting(40, 3, |k| if k < 20 { [-1.5, -3.5] } else { [1.5, -3.9] }),
            ),
            (GREEN, layer(20, [3.0, 3.5], [-3.95, -3.75])),
        ],
    );
    assert_eq!(conflict.density.order(BLUE, PINK), DensityOrder::Unknown);
    assert_eq!(
        conflict.density.conflicts,
        [(BLUE.to_string(), PINK.to_string())]
    );
    assert!(conflict.density.relations.is_empty());
    // With more particles on the right, the right cup outweighs the left.
    let outweighed = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (
                BLUE,
                resting(50, 3, |k| if k < 20 { [-1.5, -3.9] } else { [1.5, -3.5] }),
            ),
            (
                PINK,
                resting(50, 3, |k| if k < 20 { [-1.5, -3.5] } else { [1.5, -3.9] }),
            ),
            (GREEN, layer(20, [3.0, 3.5], [-3.95, -3.75])),
        ],
    );
    assert_eq!(outweighed.density.order(PINK, BLUE), DensityOrder::Heavier);
    assert_eq!(outweighed.density.conflicts.len(), 1);
}

/// `count` particles sliding down the test stick at `speed` units/s, one starting per frame
/// for the first `count` frames of 30.
fn sliding(count: usize, speed: f64) -> SoftBodyTrack {
    let (start, end) = ([-1.0, 1.0], [1.0, 0.0]);
    let length = f64::hypot(end[0] - start[0], end[1] - start[1]);
    let particles = (0..30)
        .map(|frame: usize| {
            (0..count.min(frame + 1))
                .map(|k| {
                    #[expect(clippy::cast_precision_loss, reason = "small test counts")]
                    let travelled = speed * FRAME_SECONDS * (frame - k) as f64;
                    let t = (travelled / length).min(1.0);
                    [
                        start[0] + t * (end[0] - start[0]),
                        start[1] + t * (end[1] - start[1]),
                        0.0,
                    ]
                })
                .collect()
        })
        .collect();
    SoftBodyTrack { particles }
}

#[test]
fn slow_fluids_on_a_stick_are_sticky_fast_ones_are_not() {
    let inference = infer(
        &[BLUE, PINK, GREEN],
        vec![
            (BLUE, sliding(10, 0.2)),
            (PINK, sliding(10, 2.0)),
            // Green falls straight down far from the stick: no evidence.
            (
                GREEN,
                SoftBodyTrack {
                    particles: (0..30_u32)
                        .map(|frame| {
                            let y = 2.5 - 0.05 * f64::from(frame);
                            vec![[2.4, y, 0.0]; 5]
                        })
                        .collect(),
                },
            ),
        ],
    );
    let classes: Vec<(&str, Option<Viscosity>)> = inference
        .viscosity
        .iter()
        .map(|v| (v.fluid.as_str(), v.class))
        .collect();
    assert_eq!(
        classes,
        [
            (BLUE, Some(Viscosity::Sticky)),
            (PINK, Some(Viscosity::NonSticky)),
            (GREEN, None)
        ]
    );
    let blue = &inference.viscosity[0];
    assert!((blue.median_speed.unwrap() - 0.2).abs() < 1e-9, "{blue:?}");
    assert_eq!(blue.particles, 10);
    assert_eq!(inference.viscosity[2].samples, 0);
}

#[test]
fn bad_tracks_are_errors_naming_video_and_fluid() {
    let scene = scene(&[BLUE, PINK, GREEN]);
    let missing = four_d(vec![(BLUE, layer(5, [0.0, 1.0], [0.0, 1.0]))]);
    assert_eq!(
        infer_fluid_properties("7", &scene, &missing)
            .unwrap_err()
            .to_string(),
        "video `7`: fluid `Pink Fluid` has no tracked particles in outputs4D.json"
    );
    let stranger = four_d(vec![("Teal Fluid", layer(5, [0.0, 1.0], [0.0, 1.0]))]);
    assert_eq!(
        infer_fluid_properties("7", &scene, &stranger)
            .unwrap_err()
            .to_string(),
        "video `7`: outputs4D.json tracks `Teal Fluid`, which is not a fluid of the scene"
    );
    let mut broken = layer(5, [0.0, 1.0], [0.0, 1.0]);
    broken.particles[1][2][1] = f64::NAN;
    let broken = four_d(vec![
        (BLUE, broken),
        (PINK, layer(5, [0.0, 1.0], [0.0, 1.0])),
        (GREEN, layer(5, [0.0, 1.0], [0.0, 1.0])),
    ]);
    assert_eq!(
        infer_fluid_properties("7", &scene, &broken)
            .unwrap_err()
            .to_string(),
        "video `7`: fluid `Blue Fluid` particle 2 at frame 1 is not finite"
    );
    let two = four_d(vec![
        (BLUE, layer(5, [0.0, 1.0], [0.0, 1.0])),
        (PINK, layer(5, [0.0, 1.0], [0.0, 1.0])),
    ]);
    // Two fluids (perception missed one): the 3-fluid pool's ends.
    let inferred = infer_fluid_properties("7", &self::scene(&[BLUE, PINK]), &two).unwrap();
    let mut densities: Vec<f64> = inferred.ranks.iter().map(|rank| rank.density).collect();
    densities.sort_by(f64::total_cmp);
    assert_eq!(densities, vec![1600.0, 4400.0]);
    // Five (perception read a spurious one): the 4-fluid pool's range, evenly spaced.
    let (orange, cyan) = ("Orange Fluid", "Cyan Fluid");
    let five = four_d(
        [BLUE, PINK, GREEN, orange, cyan]
            .into_iter()
            .map(|fluid| (fluid, layer(5, [0.0, 1.0], [0.0, 1.0])))
            .collect(),
    );
    let scene = self::scene(&[BLUE, PINK, GREEN, orange, cyan]);
    let inferred = infer_fluid_properties("7", &scene, &five).unwrap();
    let mut densities: Vec<f64> = inferred.ranks.iter().map(|rank| rank.density).collect();
    densities.sort_by(f64::total_cmp);
    assert_eq!(densities, vec![1200.0, 2250.0, 3300.0, 4350.0, 5400.0]);
    let none = four_d(Vec::new());
    assert_eq!(
        infer_fluid_properties("7", &self::scene(&[]), &none)
            .unwrap_err()
            .to_string(),
        "video `7`: no fluid was seen (the release has 3 or 4)"
    );
}

#[test]
fn the_demo_video_gives_its_true_order_and_classes() {
    // Generated: light blue (4400, non-sticky, with a later emitter) is denser than yellow
    // (3000, sticky), denser than pink (1600, non-sticky); the truth relates every pair. The
    // video shows light blue below yellow (purple cup) and below pink (pink cup); yellow meets
    // pink as 4 particles in the pink cup, which lie below pink: every pair is decided right.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/fluid_slides/0");
    let annotation = FluidAnnotation::load(&dir.join("outputs.json")).unwrap();
    let four_d = FourDData::load(&dir.join("outputs4D.json")).unwrap();
    let scene = PerceivedFluidScene::from_layout(&annotation.layout);
    let inference = infer_fluid_properties("0", &scene, &four_d).unwrap();
    let truth = annotation.tracking.density_ordering();
    let fluids: Vec<&str> = scene.fluids.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(fluids, ["Pink Fluid", "Yellow Fluid", "Light Blue Fluid"]);
    for first in &fluids {
        for second in &fluids {
            if first == second {
                continue;
            }
            assert_eq!(
                inference.density.order(first, second),
                truth.order(first, second),
                "{first} against {second}"
            );
        }
    }
    for (evidence, fluid) in inference.viscosity.iter().zip(&annotation.layout.fluids) {
        assert_eq!(evidence.class, Some(fluid.viscosity), "{evidence:?}");
    }
    for rank in &inference.ranks {
        let fluid = annotation
            .layout
            .fluids
            .iter()
            .find(|f| f.name == rank.fluid);
        assert_eq!(fluid.map(|f| f.density), Some(rank.density), "{rank:?}");
    }
}
