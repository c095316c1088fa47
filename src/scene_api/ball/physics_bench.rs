//! `bench physics --scenario ball`: the ball simulation's error against its run time over grid
//! spacing, particles per cell (per ball: about `π (r/dx)² ppc²`) and the substep's CFL
//! number, each point compared with a run at a fine reference (grid spacing 0.03 units, two
//! particles per cell side, CFL 0.25). One more point is the reference with every ball started
//! 0.001 units to the right: the difference chaos alone makes, the floor no resolution gets
//! under.
//!
//! The cases are the scenes of generated videos (default: the demo videos), started from the
//! release positions with the true materials: the factual run (all three balls) and every
//! counterfactual run (a floating wall and two balls removed). Three error measures, per ball:
//! * `pit_disagreement`: each ball's two labels "drops into the left pit", "drops into the right
//!   pit" against the reference's, the share that differ: what the questions read, so the
//!   default should agree on 99% of them;
//! * `drop_time_error`: when the ball's centre drops below the pit line, in video lengths (4 s:
//!   0.05 is 0.2 s), 0 for a ball that never drops;
//! * `shape_error`: its final elongation (`√(λ₁/λ₂) − 1` of its particles: a plastic ball's
//!   dent) against the reference's.
//!
//! The cost of a point is its wall time and the solver's particle substeps (`work`).
//!
//! Input: video folders with an `outputs.json`. Output: the cases of [`BENCH`].

use std::path::PathBuf;

use super::simulate::{BallModel, BallStart, Stadium, UPDATE_SECONDS, run};
use crate::dataset::ball::BallAnnotation;
use crate::dataset::ball::outcome::{MAX_UPDATES, Pit};
use crate::physics::bench::{
    BenchCase, BenchError, CaseOutput, ErrorMeasure, Parameter, PhysicsBench, Reduction, Reference,
    video_name,
};

/// The ball simulation's benchmark.
pub(crate) const BENCH: PhysicsBench = PhysicsBench {
    // The longest run: 2,000 updates of 1/60 s.
    duration: 2000.0 / 60.0,
    parameters: &[
        Parameter {
            key: "grid_spacing",
            flag: "--grid-spacing",
            label: "dx",
        },
        Parameter {
            key: "particles_per_cell_side",
            flag: "--particles-per-cell",
            label: "ppc",
        },
        Parameter {
            key: "cfl",
            flag: "--cfl",
            label: "cfl",
        },
        Parameter {
            key: "start_shift",
            flag: "--start-shift",
            label: "shift",
        },
    ],
    sweep: &[
        &[0.2, 2.0, 0.5, 0.0],
        &[0.15, 2.0, 0.5, 0.0],
        &[0.1, 1.0, 0.5, 0.0],
        &[0.1, 2.0, 0.5, 0.0],
        &[0.1, 2.0, 0.25, 0.0],
        &[0.075, 2.0, 0.5, 0.0],
        &[0.05, 2.0, 0.5, 0.0],
        // The reference itself with every ball started a thousandth of a unit to the right.
        &[0.03, 2.0, 0.25, 0.001],
    ],
    default: &[0.1, 2.0, 0.5, 0.0],
    reference: Reference::Point(&[0.03, 2.0, 0.25, 0.0]),
    errors: &[
        ErrorMeasure {
            key: "pit_disagreement",
            reduction: Reduction::Mean,
            tolerance: Some(0.01),
            plotted: false,
        },
        ErrorMeasure {
            key: "drop_time_error",
            reduction: Reduction::Mean,
            tolerance: Some(0.05),
            plotted: true,
        },
        ErrorMeasure {
            key: "shape_error",
            reduction: Reduction::Largest,
            tolerance: Some(0.05),
            plotted: true,
        },
    ],
    error_axis: "error: drop time in video lengths, elongation",
    repeats: 1,
    title: "MPM balls",
    uses_videos: true,
    cases,
};

/// Which balls a case runs, without which floating wall.
#[derive(Debug, Clone)]
struct CaseScene {
    stadium: Stadium,
    balls: Vec<BallStart>,
    removed: Option<usize>,
}

/// The factual and every counterfactual case of every video.
fn cases(videos: &[PathBuf]) -> Result<Vec<BenchCase>, BenchError> {
    let mut cases = Vec::new();
    for video in videos {
        let name = video_name(video);
        let annotation = BallAnnotation::load(&video.join("outputs.json"))
            .map_err(|error| BenchError::new(&name, error))?;
        let stadium = Stadium::from_layout(&annotation.layout);
        let starts: Vec<BallStart> = annotation
            .layout
            .balls
            .iter()
            .map(|ball| BallStart {
                material: ball.elasticity,
                centre: [ball.release_position[0], ball.release_position[1]],
                velocity: [0.0; 2],
                angular_velocity: 0.0,
            })
            .collect();
        let mut scenes = vec![(
            format!("{name} factual"),
            CaseScene {
                stadium: stadium.clone(),
                balls: starts.clone(),
                removed: None,
            },
        )];
        for (wall_index, wall) in annotation.layout.floating_walls.iter().enumerate() {
            for (ball, start) in annotation.layout.balls.iter().zip(&starts) {
                scenes.push((
                    format!("{name} {} without the {}", ball.name, wall.name),
                    CaseScene {
                        stadium: stadium.clone(),
                        balls: vec![*start],
                        removed: Some(wall_index),
                    },
                ));
            }
        }
        for (case_name, scene) in scenes {
            let label = case_name.clone();
            cases.push(BenchCase {
                name: case_name,
                exact: None,
                run: Box::new(move |point| measure(&scene, &label, point)),
            });
        }
    }
    Ok(cases)
}

/// Seconds of one video (240 updates), the unit of the drop time error.
const VIDEO_SECONDS: f64 = 4.0;

/// A case at `point` (grid spacing, particles per cell side, CFL, start shift in units): each
/// ball's two pit labels, its drop time (video lengths, 0 when it never drops) and its final
/// elongation.
fn measure(scene: &CaseScene, case: &str, point: &[f64]) -> Result<CaseOutput, BenchError> {
    let [spacing, per_side, cfl, shift] = *point else {
        return Err(BenchError::new(
            case,
            "a sweep point needs a grid spacing, a count, a CFL number and a shift",
        ));
    };
    if !(spacing.is_finite() && (0.01..=0.5).contains(&spacing)) {
        return Err(BenchError::new(
            case,
            format!("grid spacing must be 0.01 to 0.5 units, not {spacing}"),
        ));
    }
    if !((1.0..=6.0).contains(&per_side) && per_side.fract() == 0.0) {
        return Err(BenchError::new(
            case,
            format!("particles per cell side must be 1 to 6, not {per_side}"),
        ));
    }
    if !(cfl > 0.0 && cfl <= 1.0) {
        return Err(BenchError::new(
            case,
            format!("the CFL number must be in (0, 1], not {cfl}"),
        ));
    }
    if !shift.is_finite() || shift.abs() > 0.1 {
        return Err(BenchError::new(
            case,
            format!("a start shift must be within ±0.1 units, not {shift}"),
        ));
    }
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "checked to be a whole number from 1 to 6"
    )]
    let model = BallModel {
        spacing,
        particles_per_cell: per_side as usize,
        cfl,
        ..BallModel::default()
    };
    let balls: Vec<BallStart> = scene
        .balls
        .iter()
        .map(|ball| BallStart {
            centre: [ball.centre[0] + shift, ball.centre[1]],
            ..*ball
        })
        .collect();
    let tracks = run(&scene.stadium, scene.removed, &balls, &model, MAX_UPDATES)
        .map_err(|error| BenchError::new(case, error))?;
    let mut pits = Vec::new();
    let mut times = Vec::new();
    let label = |holds: bool| if holds { 1.0 } else { 0.0 };
    for index in 0..balls.len() {
        let dropped = tracks.drop_of(index);
        for side in Pit::BOTH {
            pits.push(label(dropped.is_some_and(|(pit, _)| pit == side)));
        }
        times.push(dropped.map_or(0.0, |(_, update)| {
            update as f64 * UPDATE_SECONDS / VIDEO_SECONDS
        }));
    }
    Ok(CaseOutput {
        quantities: vec![pits, times, tracks.shapes],
        work: Some(tracks.particle_substeps),
    })
}
