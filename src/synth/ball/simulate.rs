//! The runs of a ball scene on the truth solver (`physics::shape_matching`): the factual run with
//! all three balls, captured for the video and continued until every ball has dropped or
//! settled, and the counterfactual runs with one floating wall and the other two balls removed.
//!
//! A run ends at [`MAX_UPDATES`], or once every simulated ball has dropped out of the stadium or
//! lies still ([`track_finished`]). The release ran on until the balls dropped or to update
//! 2000; a ball lying still in a static scene never moves again, so its label is the same and
//! the rest of the run is skipped.

use crate::dataset::ball::ElasticityType;
use crate::dataset::ball::outcome::{
    CAPTURE_UPDATES, MAX_UPDATES, PitRecord, RunMode, label_ball, track_finished,
};
use crate::physics::shape_matching::{
    ELASTIC, PLASTIC, RIGID, Slab, SoftBodyError, SoftBodyParameters, SoftBodyWorld, SoftMaterial,
};
use crate::physics::vector3::Matrix;

use super::layout::{BALL_RADIUS, Layout};

/// Each ball's mass, kg (the release's balls are one prefab size; equal masses).
const BALL_MASS: f64 = 1.0;

/// The solver material of a release material.
pub fn material(kind: ElasticityType) -> SoftMaterial {
    match kind {
        ElasticityType::Elastic => ELASTIC,
        ElasticityType::Rigid => RIGID,
        ElasticityType::Plastic => PLASTIC,
    }
}

/// What a run simulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunKind {
    /// All balls, all walls.
    Factual,
    /// Ball `ball` alone, floating wall `wall` removed (indices into the layout's lists).
    Counterfactual {
        /// The removed floating wall.
        wall: usize,
        /// The one ball.
        ball: usize,
    },
}

/// One ball's state in a captured frame.
#[derive(Debug, Clone, PartialEq)]
pub struct BallFrame {
    /// Particle positions, units.
    pub particles: Vec<[f64; 3]>,
    /// The particles' centre, units.
    pub centre: [f64; 3],
    /// The map from the ball's rest shape to its current shape (drawing).
    pub deformation: Matrix,
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct BallRun {
    /// Layout indices of the simulated balls.
    pub balls: Vec<usize>,
    /// Each simulated ball's label.
    pub records: Vec<PitRecord>,
    /// Captured frames (factual runs only): frame `j` after update `2j + 2`, per simulated ball.
    pub frames: Vec<Vec<BallFrame>>,
    /// Updates simulated.
    pub updates: usize,
}

/// The slabs of a layout as colliders, without floating wall `removed`.
pub fn slabs(layout: &Layout, removed: Option<usize>) -> Vec<Slab> {
    let walls = layout
        .floating_walls
        .iter()
        .enumerate()
        .filter(|(index, _)| Some(*index) != removed)
        .map(|(_, wall)| wall);
    layout
        .ramps
        .iter()
        .chain(&layout.floor_pieces)
        .chain(walls)
        .map(|slab| Slab {
            start: slab.start,
            end: slab.end,
            thickness: slab.thickness,
        })
        .collect()
}

/// Runs `kind` on `layout`.
///
/// # Errors
/// The solver's, should a particle stop being finite.
pub fn run(layout: &Layout, kind: RunKind) -> Result<BallRun, SoftBodyError> {
    let (removed, balls, mode) = match kind {
        RunKind::Factual => (None, (0..layout.balls.len()).collect(), RunMode::Factual),
        RunKind::Counterfactual { wall, ball } => (Some(wall), vec![ball], RunMode::Counterfactual),
    };
    let mut world = SoftBodyWorld::new(SoftBodyParameters::default(), slabs(layout, removed))?;
    for &index in &balls {
        if let Some(ball) = layout.balls.get(index) {
            world.add_sphere(
                ball.release,
                BALL_RADIUS,
                BALL_MASS,
                material(ball.elasticity),
            )?;
        }
    }
    let mut centres: Vec<Vec<[f64; 2]>> = vec![Vec::new(); balls.len()];
    let mut frames = Vec::new();
    let mut updates = 0;
    while updates < MAX_UPDATES {
        world.step()?;
        updates += 1;
        for (track, body) in centres.iter_mut().zip(world.bodies()) {
            let centre = body.centre();
            track.push([centre[0], centre[1]]);
        }
        if mode == RunMode::Factual && updates <= CAPTURE_UPDATES && updates % 2 == 0 {
            frames.push(
                world
                    .bodies()
                    .iter()
                    .map(|body| BallFrame {
                        particles: body.positions().to_vec(),
                        centre: body.centre(),
                        deformation: body.deformation(),
                    })
                    .collect(),
            );
        }
        let captured = mode == RunMode::Counterfactual || updates >= CAPTURE_UPDATES;
        if captured && centres.iter().all(|track| track_finished(track)) {
            break;
        }
    }
    let records = centres
        .iter()
        .map(|track| label_ball(track, mode))
        .collect();
    Ok(BallRun {
        balls,
        records,
        frames,
        updates,
    })
}
