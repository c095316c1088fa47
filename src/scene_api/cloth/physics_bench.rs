//! `bench physics --scenario cloth`: the cloth simulation's error against its run time over the
//! cloth's grid (particles along a side), the solver's substeps per update and its iterations
//! per substep, each point compared with a fine reference (the video's 31 × 31 grid, 50
//! substeps of 4 iterations: ten times the default's 20 constraint passes an update).
//!
//! The cases are the halves of generated videos (default: the demo videos), as the release made
//! them: the boxes at their start poses with their true masses, the cloth with its true stretch,
//! bending and friction, spawned flat where the release spawns it (at the middle of its height
//! range) and pulled the release's mean 5 units. Three error measures:
//! * `pose_disagreement`: the share of boxes whose end pose differs from the reference's;
//! * `contact_disagreement`: the share of the half's box pairs whose two labels, "collide at
//!   some point" and "touch at the end", differ from the reference's;
//! * `box_position_error`: the mean absolute difference of the boxes' end centres' coordinates
//!   from the reference's, units.
//!
//! The cost of a point is its wall time and the solver's particle constraint passes (`work`:
//! particles × substeps × iterations × updates).
//!
//! Input: video folders with an `outputs.json`. Output: the cases of [`BENCH`].

use std::path::PathBuf;

use super::simulate::{ClothModel, SeenBox, SeenCloth, SeenHalf, simulate_half};
use crate::dataset::cloth::ClothAnnotation;
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::outcome::Pose;
use crate::physics::bench::{
    BenchCase, BenchError, CaseOutput, ErrorMeasure, Parameter, PhysicsBench, Reduction, Reference,
    video_name,
};
use crate::synth::cloth::layout::{
    CLOTH_HEIGHT, CLOTH_RESOLUTION, CLOTH_SIDE, CLOTH_START_Z, HALF_CENTRES,
};

/// The cloth simulation's benchmark.
pub(crate) const BENCH: PhysicsBench = PhysicsBench {
    // Updates 0 to 288 of 1/60 s.
    duration: 288.0 / 60.0,
    parameters: &[
        Parameter {
            key: "sheet_resolution",
            flag: "--sheet-resolution",
            label: "n",
        },
        Parameter {
            key: "substeps",
            flag: "--substeps",
            label: "sub",
        },
        Parameter {
            key: "iterations",
            flag: "--iterations",
            label: "it",
        },
    ],
    sweep: &[
        &[16.0, 5.0, 2.0],
        &[21.0, 10.0, 2.0],
        &[31.0, 5.0, 2.0],
        &[31.0, 10.0, 1.0],
        &[31.0, 10.0, 2.0],
        &[31.0, 20.0, 2.0],
        &[31.0, 10.0, 4.0],
    ],
    default: &[31.0, 10.0, 2.0],
    reference: Reference::Point(&[31.0, 50.0, 4.0]),
    errors: &[
        ErrorMeasure {
            key: "pose_disagreement",
            reduction: Reduction::Mismatch,
            tolerance: Some(0.01),
            plotted: true,
        },
        ErrorMeasure {
            key: "contact_disagreement",
            reduction: Reduction::Mean,
            tolerance: Some(0.01),
            plotted: true,
        },
        ErrorMeasure {
            key: "box_position_error",
            reduction: Reduction::Mean,
            tolerance: None,
            plotted: false,
        },
    ],
    error_axis: "share of box poses and contact labels unlike the reference's",
    repeats: 1,
    title: "XPBD cloth and boxes",
    uses_videos: true,
    cases,
};

/// The release's spawn height offset is U(0, 0.3): the middle of its range, units.
const SPAWN_OFFSET: f64 = 0.15;
/// The release's mean pull distance, 4.8 + U(−0.1, 0.5), units.
const PULL: f64 = 5.0;

/// Both halves of every video.
fn cases(videos: &[PathBuf]) -> Result<Vec<BenchCase>, BenchError> {
    let mut cases = Vec::new();
    for video in videos {
        let name = video_name(video);
        let annotation = ClothAnnotation::load(&video.join("outputs.json"))
            .map_err(|error| BenchError::new(&name, error))?;
        for side in Side::BOTH {
            let half = release_half(&annotation, side);
            let label = format!("{name} {} half", side.word());
            let case_label = label.clone();
            cases.push(BenchCase {
                name: label,
                exact: None,
                run: Box::new(move |point| measure(&half, &case_label, point)),
            });
        }
    }
    Ok(cases)
}

/// `side`'s half as the release made it (see the module's doc).
fn release_half(annotation: &ClothAnnotation, side: Side) -> SeenHalf {
    let boxes = annotation
        .objects(side)
        .boxes()
        .map(|record| SeenBox::from_record(record, Some(record.mass)))
        .collect();
    let centre = match side {
        Side::Left => HALF_CENTRES[0],
        Side::Right => HALF_CENTRES[1],
    };
    let spacing = CLOTH_SIDE / (CLOTH_RESOLUTION - 1) as f64;
    let spawn = (0..CLOTH_RESOLUTION * CLOTH_RESOLUTION)
        .map(|k| {
            let (column, row) = (k % CLOTH_RESOLUTION, k / CLOTH_RESOLUTION);
            [
                centre - CLOTH_SIDE / 2.0 + column as f64 * spacing,
                CLOTH_HEIGHT + SPAWN_OFFSET,
                CLOTH_START_Z - CLOTH_SIDE + row as f64 * spacing,
            ]
        })
        .collect();
    let cloth = annotation.cloth(side);
    SeenHalf {
        boxes,
        cloth: SeenCloth {
            spawn,
            stretch_compliance: cloth.stretching_compliance,
            max_bending: cloth.bending_compliance,
            friction: Some(cloth.friction),
            pull_distance: PULL,
        },
    }
}

/// A case at `point` (cloth resolution, substeps, iterations): each box's end pose (as its
/// index among the poses), each pair's collision and touch labels, each box's end centre.
fn measure(half: &SeenHalf, case: &str, point: &[f64]) -> Result<CaseOutput, BenchError> {
    let [resolution, substeps, iterations] = *point else {
        return Err(BenchError::new(
            case,
            "a sweep point needs a cloth resolution, substeps and iterations",
        ));
    };
    let whole = |value: f64, low: f64, high: f64, what: &str| -> Result<usize, BenchError> {
        if (low..=high).contains(&value) && value.fract() == 0.0 {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a whole number checked to lie in a small range"
            )]
            Ok(value as usize)
        } else {
            Err(BenchError::new(
                case,
                format!("{what} must be a whole number from {low} to {high}, not {value}"),
            ))
        }
    };
    let model = ClothModel {
        resolution: whole(resolution, 3.0, 61.0, "the cloth resolution")?,
        substeps: whole(substeps, 1.0, 200.0, "substeps")?,
        iterations: whole(iterations, 1.0, 20.0, "iterations")?,
        ..ClothModel::default()
    };
    let run = simulate_half(half, &model).map_err(|error| BenchError::new(case, error))?;
    let poses = run
        .end_poses
        .iter()
        .map(|pose| Pose::ALL.iter().position(|p| p == pose).unwrap_or(0) as f64)
        .collect();
    let count = half.boxes.len();
    let mut contacts = Vec::new();
    for first in 0..count {
        for second in first + 1..count {
            let pair = (first, second);
            contacts.push(f64::from(u8::from(run.collided.contains(&pair))));
            contacts.push(f64::from(u8::from(run.touching.contains(&pair))));
        }
    }
    let positions = run
        .end_states
        .iter()
        .flat_map(|(position, _)| *position)
        .collect();
    // Particle constraint passes: every iteration of every substep visits every particle.
    let passes = model.resolution * model.resolution * model.substeps * model.iterations;
    let work = u64::try_from(passes.saturating_mul(run.updates)).unwrap_or(u64::MAX);
    Ok(CaseOutput {
        quantities: vec![poses, contacts, positions],
        work: Some(work),
    })
}
