//! The ball engine's view of a video: the balls and floating walls it can refer to by colour.
//!
//! An object is referred to by its colour word alone (`pink ball`, `white floating wall`), as the
//! paper's templates do. The release gives the three balls distinct colours and the four slabs
//! distinct colours; a ball may share a wall's colour, which the kind word tells apart. Should
//! two objects of one kind share a colour, neither is asked about.

use crate::dataset::ball::names::parse_ball_object_name;
use crate::dataset::ball::{BallAnnotation, BallRecord, ElasticityType};

/// An object the engine can ask about.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Reference<'a> {
    /// Its annotation name (`Light Blue Ball`).
    pub(super) name: &'a str,
    /// Its colour as questions write it (`light blue`).
    pub(super) word: String,
}

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

/// The objects of `names` with their colour words, leaving out every object whose colour word
/// another of them shares.
fn references<'a>(names: impl Iterator<Item = &'a str>) -> Vec<Reference<'a>> {
    let named: Vec<Reference<'a>> = names
        .filter_map(|name| {
            let word = parse_ball_object_name(name)?.color?.to_lowercase();
            Some(Reference { name, word })
        })
        .collect();
    named
        .iter()
        .filter(|reference| named.iter().filter(|o| o.word == reference.word).count() == 1)
        .cloned()
        .collect()
}
