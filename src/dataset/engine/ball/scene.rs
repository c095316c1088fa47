//! The ball engine's view of a video: the balls and floating walls it can refer to by colour.
//!
//! An object is referred to by its colour word alone (`pink ball`, `white floating wall`), as the
//! paper's templates do. The release gives the three balls distinct colours and the four slabs
//! distinct colours; a ball may share a wall's colour, which the kind word tells apart. Should
//! two objects of one kind share a colour, neither is asked about.

use crate::dataset::ball::names::parse_ball_object_name;
use crate::dataset::ball::{BallAnnotation, BallRecord, ElasticityType};
use crate::dataset::engine::colour_references;

pub(super) use crate::dataset::engine::Reference;

/// A ball the engine can ask about, with its material.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct BallReference<'a> {
    /// Name and colour word.
    pub(super) reference: Reference<'a>,
    /// Its material.
    pub(super) elasticity: ElasticityType,
}

/// The engine's view of one video.
#[derive(Debug, Clone)]
pub(super) struct BallScene<'a> {
    /// The balls, in `metaSamplingData.balls` order.
    pub(super) balls: Vec<BallReference<'a>>,
    /// The floating walls, in `metaSamplingData.floatingWalls` order.
    pub(super) walls: Vec<Reference<'a>>,
}

impl<'a> BallScene<'a> {
    /// The view of `annotation`.
    pub(super) fn new(annotation: &'a BallAnnotation) -> BallScene<'a> {
        let layout = &annotation.layout;
        let balls = references(layout.balls.iter().map(|ball| ball.name.as_str()))
            .into_iter()
            .filter_map(|reference| {
                let record: &BallRecord = layout.ball(reference.name)?;
                Some(BallReference {
                    elasticity: record.elasticity,
                    reference,
                })
            })
            .collect();
        BallScene {
            balls,
            walls: references(layout.floating_walls.iter().map(|wall| wall.name.as_str())),
        }
    }
}

/// The objects of `names` with their colour words (see [`colour_references`]).
fn references<'a>(names: impl Iterator<Item = &'a str>) -> Vec<Reference<'a>> {
    colour_references(names, |name| {
        Some(parse_ball_object_name(name)?.color?.to_lowercase())
    })
}
